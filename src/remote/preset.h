#pragma once
// Presets (docs/remote-policies.md): how our observations and actions map to what a policy
// server expects, independent of the protocol. A preset turns an Observation into named groups
// (camera images, state vectors, the language instruction, and side-channel extras), and the
// server's action groups back into an ActionChunk in our action space. Each protocol client
// lays the groups out its own way (openpi: flat keys "observation/..."; GR00T: "video.x" /
// "state.x" or the N1.6 nested maps).
//
//   hribench (default): our native layout, every value in our units (metres, radians, seconds,
//       world frame, quaternions w,x,y,z), float64 by default; the side channel carries the
//       episode's start (and, for privileged policies served by `hribench serve`, the episode
//       and its events);
//   libero: openpi's pi05_libero inputs and 7-D end-effector delta actions;
//   droid:  openpi's pi05_droid inputs and joint-velocity actions, integrated over one control
//       step into joint_pos targets.
// Presets throw PolicyError(kWrongShape / kFailed) for a reply they cannot map; the message
// names the key.

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "policy/policy.h"
#include "remote/wire.h"

namespace hribench::remote {

struct ObservationGroups {
  std::vector<std::pair<std::string, NdArray>> video;  // uint8 (H, W, 3) per camera
  std::vector<std::pair<std::string, NdArray>> state;  // 1-D vectors
  std::string language;
  Map extras;  // side channel (hribench only); empty for the stock presets
};

// The server's actions: named groups of shape (H, D) or (H,), or one array "actions" (H, D).
using ActionGroups = std::vector<std::pair<std::string, NdArray>>;

class Preset {
 public:
  virtual ~Preset() = default;
  virtual std::string name() const = 0;
  // What the client declares to the runner (cameras, action space, replan_every default).
  virtual policy::PolicySpec spec() const = 0;
  // An episode starts; the next encode() is its first query.
  virtual void begin(const policy::EpisodeInfo& info) = 0;
  virtual ObservationGroups encode(const policy::Observation& observation) = 0;
  // The chunk for `groups` (the reply to the last encode()). The runner validates it. A reply
  // without the preset's action groups, or of other shapes: policy::PolicyError (wrong_shape).
  virtual policy::ActionChunk decode(const ActionGroups& groups) = 0;
  // The action groups and widths the preset reads, in order (the GR00T modality names).
  virtual std::vector<std::pair<std::string, int>> action_layout() const = 0;
};

struct PresetOptions {
  std::string name = "hribench";
  std::string state_dtype = "<f8";  // hribench: "<f8" or "<f4"
  // hribench: the server's declared spec (metadata "hribench/spec"), if it sent one.
  std::optional<policy::PolicySpec> served_spec;
  policy::ActionSpace space = policy::ActionSpace::kEeDelta;  // hribench without served_spec
  bool allow_privileged = false;  // privileged=1 in the reference
};

// Throws core::InputError (where "policy PROTOCOL: preset") for an unknown name, or for a
// served spec asking for the privileged track without allow_privileged.
std::unique_ptr<Preset> make_preset(const PresetOptions& options, const std::string& where);
std::vector<std::string> preset_names();  // "droid", "hribench", "libero"

// ---- the hribench layout, both ways (the client encodes, `hribench serve` decodes) ----------

// Metadata form of a spec (openpi metadata / GR00T modality answer key "hribench/spec").
Value spec_to_value(const policy::PolicySpec& spec);
policy::PolicySpec spec_from_value(const Value& value, std::string_view where);

// What `hribench serve` recovers from one query in the hribench layout: the episode start
// (present on an episode's first query) and the observation, exactly as the client had it.
struct NativeQuery {
  std::optional<policy::EpisodeInfo> start;
  policy::Observation observation;
};
NativeQuery decode_native(const ObservationGroups& groups, const policy::PolicySpec& spec);
// The reply for a chunk in the hribench layout: one array "actions" (H, D), or (named) the
// groups "eef_delta" (H, 6) or "joint_position" (H, dof), and "gripper" (H, 1).
ActionGroups encode_native_actions(const policy::ActionChunk& chunk, bool named);

}  // namespace hribench::remote
