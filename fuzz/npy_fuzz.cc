// .npy arrays, and HumanML3D joint arrays read from them.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/errors.h"
#include "human/clip_io.h"
#include "human/npy.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    hribench::human::parse_npy(bytes, "fuzz.npy");
  } catch (const hribench::core::InputError&) {
  }
  try {
    hribench::human::parse_humanml3d(bytes, 20, {}, "fuzz.npy");
  } catch (const hribench::core::InputError&) {
  }
  return 0;
}
