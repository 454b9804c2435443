// Policy references ("name?k=v&k2=v2", "scheme://address?k=v"): parsed, and built-in policies
// made from them (remote schemes are parsed only: making one would open a connection).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/errors.h"
#include "policy/registry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    hribench::policy::parse_policy_ref(text);
    if (text.substr(0, text.find('?')).find("://") == std::string_view::npos) {
      hribench::policy::make_policy(text);
    }
  } catch (const hribench::core::InputError&) {
  }
  return 0;
}
