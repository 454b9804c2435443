#pragma once
// The openpi client (docs/remote-policies.md): `openpi://HOST:PORT[?options]` evaluates a policy
// served by openpi's websocket policy server (pi0, pi0.5, ...) or by `hribench serve --protocol
// openpi`. Wire: ws://HOST:PORT, the server's metadata frame first, then one binary msgpack
// request (msgpack-numpy arrays, marker keys as bin) and one binary reply per query; a text
// frame then close 1011 is the server's error.
//
// Request keys: "observation/<name>" for each image and state group of the preset, "prompt",
// and the hribench side channel "hribench/<key>". Reply: "actions" (H, D) of any numeric dtype
// (H, the chunk length, read from the reply), or the preset's named groups.
//
// Faults end the episode with a PolicyError whose message is one line: kFailed for transport
// trouble (refused, closed, no reply within timeout, the server's error with the last line of
// its traceback, not msgpack), kWrongShape for a reply without the expected keys or shapes.
// After a fault the connection is dropped; the next reset() connects again.

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "policy/policy.h"
#include "policy/registry.h"
#include "remote/preset.h"
#include "remote/websocket.h"

namespace hribench::remote {

// What every remote client reads from its reference.
struct Endpoint {
  std::string scheme;  // "openpi" | "gr00t"
  std::string host;
  std::string port;
  std::chrono::milliseconds timeout{120000};  // per reply; longer than a first-call JIT
  std::chrono::milliseconds connect_timeout{5000};
  std::optional<int> replan_every;  // from the reference
  bool execute_while_thinking = false;  // while_thinking=continue (PolicySpec)
  PresetOptions preset;
  std::string text() const;  // "openpi://HOST:PORT"
};

// Reads host, port and the shared options (preset, timeout=SECONDS, replan_every=N,
// while_thinking=hold|continue, dtype=f8|f4, space=ee_delta|joint_pos, privileged=0|1) from `ref`; leaves protocol options in it.
// Throws core::InputError naming the reference.
Endpoint endpoint_from_ref(policy::PolicyRef& ref, const std::string& default_dtype);

// The PolicyError of a transport failure, with kCannotConnect in front when no connection could
// be made (the run counts those; docs/remote-policies.md).
policy::PolicyError transport_failure(const Endpoint& endpoint, const TransportError& error);

class OpenpiPolicy : public policy::Policy {
 public:
  // Checks GET /healthz and connects (reading the metadata frame, which may declare the
  // served policy's spec). Throws core::InputError when nothing answers there, so a run is
  // refused at once.
  explicit OpenpiPolicy(Endpoint endpoint);
  policy::PolicySpec spec() const override { return spec_; }
  void reset(const policy::EpisodeInfo& info) override;
  policy::ActionChunk act(const policy::Observation& observation) override;

  const Map& metadata() const { return metadata_; }

 private:
  void connect();  // throws TransportError / WireError
  Endpoint endpoint_;
  std::unique_ptr<WebSocketClient> ws_;
  Map metadata_;
  std::unique_ptr<Preset> preset_;
  policy::PolicySpec spec_;
};

// Request map of the openpi layout for `groups`.
Map openpi_request(ObservationGroups groups);
// The groups of an openpi request (what `hribench serve` reads).
ObservationGroups openpi_groups(const Map& request);

}  // namespace hribench::remote
