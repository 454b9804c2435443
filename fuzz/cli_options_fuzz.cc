// Option values of the command line parsed by our code rather than CLI11: --latency.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/errors.h"
#include "eval/runner.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    hribench::eval::parse_latency(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const hribench::core::InputError&) {
  }
  return 0;
}
