#pragma once
// The episode runner (DESIGN.md §4, issue 5): puts a Policy in a running world and records the
// EpisodeLog. Control at 1 / control_dt (20 Hz), physics at 500 Hz (model::kTimestep); the
// episode ends at the horizon, when success has held for MetricConstants::success_hold, or on
// trouble (invalid physics, a policy error), which ends it with that status.
//
// Policy thinking time (the latency option):
//   none      — the world waits for the policy (like peer benchmarks);
//   fixed:MS  — deterministic: after a query the world runs MS milliseconds (rounded up to
//               whole control steps) with the previous command held — the servo targets stay
//               where the last action put them — before the new chunk starts;
//   measured  — as fixed, with the policy's wall-clock time (not deterministic).
// The human never waits for the robot: the ScenarioDriver drives it every physics step.
//
// What a scenario adds to the bare simulation (the human's motion, events, predicate truths)
// comes from a ScenarioDriver. The script layer's act-graph runtime is adapted to this
// interface here in eval (eval comes after script in the layer order).

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "eval/constants.h"
#include "eval/episode_log.h"
#include "model/model.h"
#include "policy/policy.h"
#include "render/gl_context.h"
#include "script/scenario.h"
#include "sim/data.h"

namespace hribench::eval {

enum class LatencyMode { kNone, kFixed, kMeasured };

struct Latency {
  LatencyMode mode = LatencyMode::kNone;
  double fixed_seconds = 0;  // kFixed only, >= 0
};
// "none" | "fixed:MS" (MS a number of milliseconds in [0, kMaxFixedLatencyMs]) | "measured";
// throws core::InputError (where "--latency") otherwise.
inline constexpr double kMaxFixedLatencyMs = 60000;
Latency parse_latency(std::string_view text);
std::string to_string(const Latency& latency);

class ScenarioDriver {
 public:
  virtual ~ScenarioDriver() = default;
  // Names of the predicate series this driver reports (the contract's "success" among them).
  virtual std::vector<std::string> predicate_names() const = 0;
  // Called after sim::reset at the start of an episode.
  virtual void reset(const model::Model& model, sim::Data& data) = 0;
  // Before every physics step: pose the human for data.time() (sim::set_human_pose).
  virtual void drive(const model::Model& model, sim::Data& data) = 0;
  // After every control step (derived quantities current): the truth of each predicate series
  // (aligned with predicate_names) and the events that happened since the last call
  // (appended to `events`, times <= data.time()).
  virtual void observe(const model::Model& model, const sim::Data& data,
                       std::vector<uint8_t>& predicates, std::vector<Event>& events) = 0;
  // The sampled episode behind this driver, for privileged policies (null: none).
  virtual std::shared_ptr<const script::EpisodeSpec> episode() const { return nullptr; }
};

// No script: the human (if any) stands at its start pose; one series, "success", never true.
class StandingHumanDriver : public ScenarioDriver {
 public:
  std::vector<std::string> predicate_names() const override { return {"success"}; }
  void reset(const model::Model&, sim::Data&) override {}
  void drive(const model::Model&, sim::Data&) override {}
  void observe(const model::Model&, const sim::Data&, std::vector<uint8_t>& predicates,
               std::vector<Event>&) override {
    predicates.assign(1, 0);
  }
};

// Identity of the episode, copied into the log and EpisodeInfo.
struct EpisodeSetup {
  std::string task;
  std::string role;
  std::string spec_hash;
  uint64_t seed = 0;
  std::string instruction;
  std::string policy;  // the policy reference, e.g. "noop"
};

struct RunOptions {
  double control_dt = 0.05;  // s; a whole number of physics steps
  double horizon = 30.0;     // s
  Latency latency;
  bool stop_on_success = true;  // end once "success" has held for constants.success_hold
  MetricConstants constants;
  // GL back end for the cameras a policy asks for (one renderer per requested camera, made for
  // this episode's model). kNone refuses camera-asking policies.
  render::Backend render_backend = render::Backend::kOsmesa;
};

// Runs one episode from sim::reset. Never throws for trouble inside the episode (tier 3: the
// log's status says what happened); throws core::InputError for options it cannot honour
// (a camera the model does not have, cameras with render_backend kNone, no usable GL context,
// a control_dt that is not a whole number of physics steps, a non-positive horizon).
// Observations: proprioception always; camera images rendered after every control step the
// policy is asked at (only then); the state track and the privileged track (events so far,
// the sampled episode in EpisodeInfo) when the policy's spec asks for them.
EpisodeLog run_episode(const model::Model& model, sim::Data& data, policy::Policy& policy,
                       ScenarioDriver& driver, const EpisodeSetup& setup,
                       const RunOptions& options);

}  // namespace hribench::eval
