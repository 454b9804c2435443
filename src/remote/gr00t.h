#pragma once
// The GR00T client (docs/remote-policies.md): `gr00t://HOST:PORT[?options]` evaluates a policy
// served by Isaac-GR00T's inference service (N1.5 after the msgpack change of 2025-08-26, or
// N1.6's PolicyServer) or by `hribench serve --protocol gr00t`. Wire: ZeroMQ REQ/REP, one frame
// each way, msgpack; the request envelope {"endpoint", "data"?, "api_token"?}; arrays as
// {"__ndarray_class__": True, "as_npy": <.npy v1.0 bytes>}. Endpoints used: ping (health check
// before the run), get_modality_config (where answered: a served hribench spec), reset (N1.6,
// at each episode), get_action.
//
// era=n15 (flat): data {"video.<cam>": uint8 (1, H, W, 3), "state.<k>": (1, D),
//   "annotation.human.task_description": [instruction], "hribench.<k>": side channel}; the reply
//   {"action.<k>": (H, D) or (H,)}.
// era=n16 (nested, the default): data {"observation": {"video": {cam: (1, 1, H, W, 3)},
//   "state": {k: (1, 1, D)}, "language": {"task": [[instruction]]}}, "options": null or
//   {"hribench": side channel}}; the reply [{k: (1, H, D)}, info].
// A receive timeout is always set; after a timeout or any failure the REQ socket is closed and
// made anew (REQ/REP is lock-step), so a late reply is never taken for the next one. Faults end
// the episode as PolicyError, as for openpi (remote/openpi.h).

#include <memory>
#include <string>

#include "policy/policy.h"
#include "remote/openpi.h"
#include "remote/preset.h"

namespace hribench::remote {

enum class Gr00tEra { kN15, kN16 };

class Gr00tPolicy : public policy::Policy {
 public:
  // Pings the server (throws core::InputError if nothing answers within the connect timeout)
  // and asks for its modality config.
  Gr00tPolicy(Endpoint endpoint, Gr00tEra era, std::string api_token);
  ~Gr00tPolicy() override;
  policy::PolicySpec spec() const override { return spec_; }
  void reset(const policy::EpisodeInfo& info) override;
  policy::ActionChunk act(const policy::Observation& observation) override;

 private:
  // One request/reply; throws TransportError (no reply in `timeout`; the socket is re-made) or
  // WireError; a reply {"error": ...} or b"ERROR" throws PolicyError.
  Value call(const std::string& endpoint, const Value* data, std::chrono::milliseconds timeout);
  struct Socket;
  Endpoint endpoint_;
  Gr00tEra era_;
  std::string api_token_;
  std::unique_ptr<Socket> socket_;
  std::unique_ptr<Preset> preset_;
  policy::PolicySpec spec_;
};

// The GR00T data of an observation in `era`'s layout, and back (what `hribench serve` reads;
// the era is told by the "observation" key).
Value gr00t_request(ObservationGroups groups, Gr00tEra era);
ObservationGroups gr00t_groups(const Map& data);
// The action groups of a reply (N1.5 map or N1.6 [action, info]) with leading batch dims dropped.
ActionGroups gr00t_actions(const Value& reply);
// The reply for `groups` in `era`'s layout (hribench serve).
Value gr00t_reply(const ActionGroups& groups, Gr00tEra era);

}  // namespace hribench::remote
