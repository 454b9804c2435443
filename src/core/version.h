#pragma once
// Provenance compiled into the binary (docs/design.md).

#include <string>
#include <string_view>

namespace hribench::core {

std::string_view version();   // HRIBench version, e.g. "0.1.0"
std::string_view git_hash();  // short git hash of the build, or "unknown"
// "HRIBench VERSION (git HASH)": the code a shard of a generate or collect records, which a
// merge requires to be the same for every shard.
std::string code_identity();

}  // namespace hribench::core
