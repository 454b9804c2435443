#pragma once
// The episode runner: puts a Policy in an Episode (eval/episode.h) and steps it to the end —
// a loop over the Episode, which records the EpisodeLog. Control at 1 / control_dt (20 Hz),
// physics at 200 Hz (model::kTimestep); the episode ends at the horizon, when success has held
// for MetricConstants::success_hold, or on trouble (invalid physics, a policy error), which
// ends it with that status.
//
// Policy thinking time (the latency option):
//   none      — the world waits for the policy (like peer benchmarks);
//   fixed:MS  — deterministic: after a query the world runs MS milliseconds (rounded up to
//               whole control steps) with the previous command held — the servo targets stay
//               where the last action put them — before the new chunk starts;
//   measured  — as fixed, with the policy's wall-clock time (not deterministic).
// A policy whose spec says execute_while_thinking keeps executing the rest of its previous
// chunk (the actions after the first replan_every) during that time, holding only once they
// run out; the new chunk then starts from its first action.
// The human never waits for the robot: the ScenarioDriver drives it every physics step.

#include <functional>
#include <string>
#include <string_view>

#include "eval/episode.h"
#include "eval/episode_log.h"
#include "model/model.h"
#include "policy/policy.h"
#include "sim/data.h"

namespace hribench::eval {

// "none" | "fixed:MS" (MS a number of milliseconds in [0, kMaxFixedLatencyMs]) | "measured";
// throws core::InputError (where "--latency") otherwise.
inline constexpr double kMaxFixedLatencyMs = 60000;
Latency parse_latency(std::string_view text);
std::string to_string(const Latency& latency);

// Runs `policy` on `episode` from its reset to its end (Episode::reset, then ask the policy
// whenever no action is queued or on the way, step, with the latency of episode.options()).
// A policy that fails (reset, act, or a chunk validate_chunk refuses) ends the episode with
// status policy_error (tier 3). With `until`: stops early, the episode still running, after
// the first step (step 0 included) at which until(episode) is true. Returns the log.
const EpisodeLog& run_episode(Episode& episode, policy::Policy& policy,
                              const std::function<bool(const Episode&)>& until = nullptr);

// The same on a model, Data and driver of the caller's (an Episode borrowing them, made for
// policy.spec()). Throws core::InputError for options it cannot honour (a camera the model
// does not have, cameras with render_backend kNone, no usable GL context, a control_dt that is
// not a whole number of physics steps, a non-positive horizon). Observations: proprioception
// always; camera images rendered after every control step the policy is asked at (only then);
// the state track and the privileged track (events so far, the sampled episode in
// EpisodeInfo) when the policy's spec asks for them.
EpisodeLog run_episode(const model::Model& model, sim::Data& data, policy::Policy& policy,
                       ScenarioDriver& driver, const EpisodeSetup& setup,
                       const RunOptions& options);

}  // namespace hribench::eval
