#include "remote/remote.h"

#include <mutex>

#include "core/errors.h"
#include "policy/registry.h"
#include "remote/gr00t.h"
#include "remote/openpi.h"

namespace hribench::remote {

bool is_connect_failure(std::string_view status_reason) {
  return status_reason.find(kCannotConnect) != std::string_view::npos;
}

void register_remote_policies() {
  static std::once_flag once;
  std::call_once(once, [] {
    policy::register_policy(policy::PolicyEntry{
        "openpi",
        "a policy served by openpi's websocket server: openpi://HOST:PORT (options: preset=hribench|libero|droid, "
        "timeout=S, replan_every=N, while_thinking=hold|continue, dtype=f8|f4, space=ee_delta|joint_pos, "
        "privileged=0|1; "
        "docs/remote-policies.md)",
        [](policy::PolicyRef ref) -> std::unique_ptr<policy::Policy> {
          Endpoint endpoint = endpoint_from_ref(ref, "f8");
          policy::reject_unknown_options(ref);
          return std::make_unique<OpenpiPolicy>(std::move(endpoint));
        }});
    policy::register_policy(policy::PolicyEntry{
        "gr00t",
        "a policy served by Isaac-GR00T's ZeroMQ inference service: gr00t://HOST:PORT (options: era=n16|n15, "
        "preset=hribench, timeout=S, replan_every=N, while_thinking=hold|continue, dtype=f4|f8, space=ee_delta|joint_pos, privileged=0|1, "
        "api_token=TEXT; docs/remote-policies.md)",
        [](policy::PolicyRef ref) -> std::unique_ptr<policy::Policy> {
          Endpoint endpoint = endpoint_from_ref(ref, "f4");
          const std::string era = policy::take_option(ref, "era", "n16");
          if (era != "n15" && era != "n16") {
            throw core::InputError("policy gr00t://" + ref.address + ": era", "n15 or n16", "'" + era + "'");
          }
          const std::string token = policy::take_option(ref, "api_token", "");
          policy::reject_unknown_options(ref);
          return std::make_unique<Gr00tPolicy>(std::move(endpoint), era == "n15" ? Gr00tEra::kN15 : Gr00tEra::kN16,
                                               token);
        }});
  });
}

}  // namespace hribench::remote
