#pragma once
// Limits on outside input that hold for every reader (docs/hardening.md).

namespace hribench::core {

// Nesting depth. Every reader of outside input (YAML, JSON, BVH, scenario expressions) refuses
// nesting deeper than this with an InputError, in the function that recurses, so that no input
// can exhaust the stack. 32 is far above any file the benchmark reads or writes.
inline constexpr int kMaxNestingDepth = 32;

}  // namespace hribench::core
