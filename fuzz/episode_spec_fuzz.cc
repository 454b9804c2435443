// EpisodeSpec JSON (a pool's episodes): parsed, read, written back.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/errors.h"
#include "core/json.h"
#include "script/schema_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const hribench::core::Json json =
        hribench::core::parse_json(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.json");
    const hribench::script::EpisodeSpec spec = hribench::script::episode_from_json(json, "fuzz.json");
    hribench::core::canonical_json(hribench::script::to_json(spec));
  } catch (const hribench::core::InputError&) {
  }
  return 0;
}
