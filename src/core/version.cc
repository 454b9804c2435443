#include "core/version.h"

namespace hribench::core {

std::string_view version() { return HRIBENCH_VERSION; }
std::string_view git_hash() { return HRIBENCH_GIT_HASH; }

}  // namespace hribench::core
