// Scenario scripts: YAML reading, the schema, and the checker (script::check_text).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "script/check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  hribench::script::check_text(text, "fuzz.yaml");  // problems are returned, never thrown
  return 0;
}
