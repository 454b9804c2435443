#pragma once
// Serving our policies over the remote protocols (`hribench serve`, docs/remote-policies.md),
// in the hribench layout (remote/preset.h):
//   openpi — a websocket server: GET /healthz answers 200 "OK\n"; after the upgrade the
//            metadata frame {"hribench/spec": the policy's spec}; then one reply per request,
//            {"actions": (H, D) float64, "policy_timing": {"infer_ms"}}; an error is a text frame
//            (a Python-style traceback whose last line is "ExceptionType: message") then close
//            1011. Each connection gets its own policy instance (several eval threads may
//            connect at once).
//   GR00T  — see serve_gr00t.
// Episodes: the first request of an episode carries the side channel's "reset" (task, seed,
// robot, ... and, for privileged policies, the EpisodeSpec JSON), which resets the policy; the
// privileged policies (oracle, reactive, blind) read the episode from there and the events from
// "events". A request before any reset is an error.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "policy/policy.h"
#include "remote/preset.h"

namespace hribench::remote {

using PolicyMaker = std::function<std::unique_ptr<policy::Policy>()>;

// Serves on host:port (port 0: a free port) until `stop` is set (checked at least every 100 ms).
// on_listening(port) is called once the socket is bound. Throws core::InputError when the port
// cannot be bound.
void serve_openpi(const std::string& host, uint16_t port, const PolicyMaker& make,
                  const std::function<void(uint16_t)>& on_listening, const std::atomic<bool>& stop);
// GR00T: a ZeroMQ REP socket bound to tcp://host:port answering ping, get_modality_config
// ({"hribench/spec": the spec}), reset, get_action (either era's layout, told by the
// "observation" key; the reply in that era's form with the groups "eef_delta" or
// "joint_position", and "gripper") and kill (stops serving). Errors are {"error": "..."}.
// Requests are answered one at a time; each client socket (told apart by its ZeroMQ routing
// identity: several eval threads may connect at once) gets its own policy instance and episode,
// kept while the server runs (ZeroMQ does not tell when a client has gone).
void serve_gr00t(const std::string& host, uint16_t port, const PolicyMaker& make,
                 const std::function<void(uint16_t)>& on_listening, const std::atomic<bool>& stop);

// One served query of the hribench layout on `policy` (shared by both protocols): resets it on
// an episode's first query, then acts. `started` tracks whether an episode has begun.
policy::ActionChunk serve_query(policy::Policy& policy, const ObservationGroups& groups, bool& started);

}  // namespace hribench::remote
