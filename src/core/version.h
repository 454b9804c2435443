#pragma once
// Provenance compiled into the binary (docs/design.md).

#include <string_view>

namespace hribench::core {

std::string_view version();   // HRIBench version, e.g. "0.1.0"
std::string_view git_hash();  // short git hash of the build, or "unknown"

}  // namespace hribench::core
