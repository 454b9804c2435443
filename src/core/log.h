#pragma once
// Logging: a thin layer over spdlog so the rest of the code names one logger. Messages go to
// stderr; `set_log_level("debug")` (or the CLI's --log-level) changes the threshold.

#include <spdlog/spdlog.h>

#include <string_view>

namespace hribench::core {

// Accepts trace, debug, info, warn, error, off. Throws InputError on anything else.
void set_log_level(std::string_view level);

}  // namespace hribench::core
