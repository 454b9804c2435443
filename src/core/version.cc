#include "core/version.h"

#include "hribench_git_hash.h"  // generated at build time (cmake/git_hash.cmake)

namespace hribench::core {

std::string_view version() { return HRIBENCH_VERSION; }
std::string_view git_hash() { return HRIBENCH_GIT_HASH; }
std::string code_identity() { return "HRIBench " + std::string(version()) + " (git " + std::string(git_hash()) + ")"; }

}  // namespace hribench::core
