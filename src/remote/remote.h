#pragma once
// The remote-policy layer (docs/remote-policies.md): policies served over openpi's websocket
// protocol and GR00T's ZeroMQ protocol, evaluated as `openpi://HOST:PORT[?options]` and
// `gr00t://HOST:PORT[?options]`, and our own policies served the same way (remote/server.h).

#include <string_view>

namespace hribench::remote {

// Starts the reason of an episode whose policy could not connect (after "reset: failed: ").
inline constexpr std::string_view kCannotConnect = "cannot connect to ";
// A run stops after this many consecutive episodes could not connect (hribench eval).
inline constexpr int kMaxConnectFailures = 3;
// True when an episode's status reason says its policy could not connect.
bool is_connect_failure(std::string_view status_reason);

// Registers the "openpi" and "gr00t" schemes with policy/registry.h (idempotent).
void register_remote_policies();

}  // namespace hribench::remote
