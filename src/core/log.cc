#include "core/log.h"

#include <string>

#include "core/errors.h"

namespace hribench::core {

void set_log_level(std::string_view level) {
  const auto parsed = spdlog::level::from_str(std::string(level));
  // spdlog maps unknown names to "off"; only accept "off" when it was asked for.
  if (parsed == spdlog::level::off && level != "off") {
    throw InputError("--log-level", "one of trace, debug, info, warn, error, off",
                     "'" + std::string(level) + "'");
  }
  spdlog::set_level(parsed);
}

}  // namespace hribench::core
