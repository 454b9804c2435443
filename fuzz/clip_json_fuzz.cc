// Clip files in our JSON format (human::parse_clip_json).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/errors.h"
#include "human/clip_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    hribench::human::parse_clip_json(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.json");
  } catch (const hribench::core::InputError&) {
  }
  return 0;
}
