// .npz archives (zip, zip64 and DEFLATE through libzip), every member, and the SMPL-H import.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/errors.h"
#include "human/npy.h"
#include "human/smplh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const hribench::human::NpzArchive archive(std::string(reinterpret_cast<const char*>(data), size), "fuzz.npz");
    for (const std::string& key : archive.keys()) {
      try {
        archive.array(key);
      } catch (const hribench::core::InputError&) {
      }
    }
    hribench::human::clip_from_smplh(archive, {}, "fuzz.npz");
  } catch (const hribench::core::InputError&) {
  }
  return 0;
}
