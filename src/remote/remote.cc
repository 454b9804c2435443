#include "remote/remote.h"

#include <mutex>

#include "policy/registry.h"
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
        "timeout=S, replan_every=N, dtype=f8|f4, space=ee_delta|joint_pos, privileged=0|1; "
        "docs/remote-policies.md)",
        [](policy::PolicyRef ref) -> std::unique_ptr<policy::Policy> {
          Endpoint endpoint = endpoint_from_ref(ref, "f8");
          policy::reject_unknown_options(ref);
          return std::make_unique<OpenpiPolicy>(std::move(endpoint));
        }});
  });
}

}  // namespace hribench::remote
