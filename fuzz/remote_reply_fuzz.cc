// Replies of remote policy servers (docs/remote-policies.md): the bytes as msgpack (openpi's
// reply and GR00T's), every array in them read by its dtype, the reply's arrays decoded into
// actions by the hribench and libero presets and read as GR00T's action reply; and the bytes as
// the NPY file inside a GR00T array. Bad bytes must be a WireError (or an InputError; a
// preset's PolicyError for arrays of the wrong shapes), nothing else.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <variant>

#include "core/errors.h"
#include "policy/policy.h"
#include "remote/gr00t.h"
#include "remote/preset.h"
#include "remote/wire.h"

namespace {

namespace remote = hribench::remote;

void read_arrays(const remote::Value& value) {
  if (const auto* array = std::get_if<remote::NdArray>(&value.v)) array->to_doubles("fuzz");
  if (const auto* list = std::get_if<remote::List>(&value.v)) {
    for (const remote::Value& item : *list) read_arrays(item);
  }
  if (const auto* map = std::get_if<remote::Map>(&value.v)) {
    for (const auto& [key, item] : *map) read_arrays(item);
  }
}

void decode_with_presets(const remote::Value& reply) {
  const auto* map = std::get_if<remote::Map>(&reply.v);
  if (map == nullptr) return;
  remote::ActionGroups groups;
  for (const auto& [key, value] : *map) {
    if (const auto* array = std::get_if<remote::NdArray>(&value.v)) groups.emplace_back(key, *array);
  }
  for (const char* name : {"hribench", "libero"}) {
    remote::PresetOptions options;
    options.name = name;
    try {
      remote::make_preset(options, "fuzz")->decode(groups);
    } catch (const remote::WireError&) {
    } catch (const hribench::policy::PolicyError&) {  // the reply's shapes are not the preset's
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const remote::Value reply = remote::unpack(bytes);
    try {
      read_arrays(reply);
    } catch (const remote::WireError&) {
    }
    decode_with_presets(reply);
    remote::gr00t_actions(reply);
  } catch (const remote::WireError&) {
  } catch (const hribench::core::InputError&) {
  }
  try {
    remote::from_npy(bytes, "fuzz").to_doubles("fuzz");
  } catch (const remote::WireError&) {
  }
  return 0;
}
