// `hribench serve --policy NAME --protocol openpi|gr00t [--host H] [--port N]`: serves a built-in
// policy over a remote-policy protocol (docs/remote-policies.md), so a client stack can be tested
// against a known policy and our clients against our own server. Prints one line once
// listening ("hribench serve: oracle over openpi at ws://127.0.0.1:8000"), then serves until
// SIGINT/SIGTERM (or, for gr00t, the "kill" endpoint).

#include <atomic>
#include <csignal>
#include <cstdio>
#include <memory>
#include <string>

#include "cli/command.h"
#include "core/errors.h"
#include "policy/registry.h"
#include "remote/server.h"

namespace hribench::cli {
namespace {

std::atomic<bool> g_stop{false};

extern "C" void on_signal(int) { g_stop = true; }

struct ServeOptions {
  std::string policy;
  std::string protocol = "openpi";
  std::string host = "127.0.0.1";
  int port = -1;  // -1: the protocol's default (8000 openpi, 5555 gr00t); 0: a free port
};

int run_serve(const ServeOptions& o) {
  if (o.protocol != "openpi" && o.protocol != "gr00t") {
    throw core::InputError("--protocol", "openpi or gr00t", "'" + o.protocol + "'");
  }
  if (o.port < -1 || o.port > 65535) throw core::InputError("--port", "a port in 0..65535", std::to_string(o.port));
  if (o.policy.find("://") != std::string::npos) {
    throw core::InputError("--policy", "a built-in policy (oracle, reactive, blind, noop, random)", "'" + o.policy + "'");
  }
  policy::make_policy(o.policy);  // unknown or bad options: one line, exit 2
  const uint16_t port = static_cast<uint16_t>(o.port >= 0 ? o.port : o.protocol == "openpi" ? 8000 : 5555);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const remote::PolicyMaker make = [name = o.policy] { return policy::make_policy(name); };
  const auto listening = [&](uint16_t bound) {
    std::printf("hribench serve: %s over %s at %s://%s:%u\n", o.policy.c_str(), o.protocol.c_str(),
                o.protocol == "openpi" ? "ws" : "tcp", o.host.c_str(), static_cast<unsigned>(bound));
    std::fflush(stdout);
  };
  if (o.protocol == "openpi") {
    remote::serve_openpi(o.host, port, make, listening, g_stop);
  } else {
    remote::serve_gr00t(o.host, port, make, listening, g_stop);
  }
  return 0;
}

HRIB_REGISTER_COMMAND(
    "serve", "Serve a built-in policy over the openpi or GR00T protocol",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<ServeOptions>();
      app.add_option("--policy", o->policy, "A built-in policy reference (oracle, reactive, blind, noop, ...)")->required();
      app.add_option("--protocol", o->protocol, "openpi (websocket) or gr00t (ZeroMQ)");
      app.add_option("--host", o->host, "Address to listen on");
      app.add_option("--port", o->port, "Port (default 8000 for openpi, 5555 for gr00t; 0: a free port)");
      return [o] { return run_serve(*o); };
    });

}  // namespace
}  // namespace hribench::cli
