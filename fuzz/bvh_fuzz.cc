// BVH motion files: the parser, then the import onto our skeleton.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/errors.h"
#include "human/bvh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const hribench::human::BvhMotion motion = hribench::human::parse_bvh(text, "fuzz.bvh");
    hribench::human::clip_from_bvh(motion, {}, "fuzz.bvh");
  } catch (const hribench::core::InputError&) {
  }
  return 0;
}
