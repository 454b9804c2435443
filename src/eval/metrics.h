#pragma once
// The metrics of docs/metrics.md as pure functions of (ScenarioContract, EpisodeLog), with the
// thresholds of eval/constants.h. docs/metrics.md states every definition; the short form is
// next to each field below. A metric that does not apply to the episode is nullopt.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "eval/constants.h"
#include "eval/contract.h"
#include "eval/episode_log.h"
#include "eval/timeline.h"

namespace hribench::eval {

struct CueResult {
  std::string name;
  double cue_time = 0;                  // s, t_c
  std::optional<double> response_time;  // s, t_r (any time after t_c; nullopt: never, or premature)
  bool responded = false;               // t_r - t_c <= window
  double latency = 0;                   // s: t_r - t_c if responded, else the window
  // A go cue the robot did not wait for: at t_c it was already moving toward the goal, in a
  // motion that began before the script allowed (CueContract::motion_allowed_from).
  bool premature = false;
};

struct SyncResult {
  std::string name;
  double human_time = 0;               // s, t_h
  std::optional<double> robot_time;    // s, t_r
  double score = 0;                    // in [0, 1]
};

struct OrderResult {
  std::string description;  // e.g. "take after offer.hold_stable"
  bool applicable = true;
  bool satisfied = true;
};

// Failure-mode labels, in docs/metrics.md's priority order.
enum class FailureLabel {
  kInvalid, kPolicyError, kCriticalContact, kContact, kCollision, kPremature, kWrongTarget,
  kIgnoredContradiction, kNoResponse, kDesync, kUnsafeProximity, kDrop, kNoRecovery,
  kManipulation, kTimeout,
};
inline constexpr int kNumFailureLabels = 15;
std::string_view to_string(FailureLabel label);

struct EpisodeMetrics {
  // CSR/CT: success holds for the last success_hold s, OC = 1, no critical contact, status ok;
  // and, where the contract asks, no human contact and violation_time within its bound.
  bool success = false;
  std::optional<double> success_since;  // start of the final run of success (if it held at end)
  double completion_time = 0;           // CT: success_since if success, else the horizon
  std::optional<double> idle_ratio;     // IR
  // Coordination.
  std::vector<CueResult> cues;
  std::optional<double> response_latency;  // Rsp: mean latency over cues
  std::vector<SyncResult> syncs;
  std::optional<double> tsync;              // mean score over applicable syncs
  std::vector<OrderResult> orders;
  std::optional<double> order_compliance;   // OC: satisfied / applicable
  // Safety.
  bool human_contact = false;        // robot–human contact outside a permitted pair and phase
  bool environment_collision = false;
  bool collision_free = true;        // CFR (per episode)
  double max_human_force = 0;        // N, over all human contacts
  bool above_quasi_static = false;   // a human contact above its region's quasi-static limit
  bool critical_contact = false;     // ... above transient_factor x the limit
  double monitored_time = 0;         // s, d(t) <= monitored_distance
  double violation_time = 0;         // s
  double hcs = 1;                    // HCS
  std::optional<double> cir;         // 1/0 on contradiction episodes
  std::optional<double> dsr;         // 1/0 on disruption episodes
  // Fluency (fractions of the episode's duration, F-DEL in s).
  std::optional<double> r_idle;
  std::optional<double> h_idle;
  std::optional<double> c_act;
  std::optional<double> f_del;
  // Failure modes: every label that applies (in priority order); the primary label is the
  // first of them, set only for failed episodes.
  std::vector<FailureLabel> labels;
  std::optional<FailureLabel> primary_label;
};

// Resolves an event name of the contract against the log (see contract.h): log events,
// "ROBOT_ACT.start" (detected onsets), "episode.start", "episode.end". nullopt: never happened.
std::optional<double> resolve_event(const ScenarioContract& contract, const EpisodeLog& log,
                                    std::string_view name, const MetricConstants& c);

// Response onsets of the contract's robot acts, in contract order (nullopt: never started).
std::vector<std::optional<double>> robot_act_onsets(const ScenarioContract& contract,
                                                    const EpisodeLog& log,
                                                    const MetricConstants& c);

// Time of the first step of the final unbroken run in which predicate series `index` is true,
// or nullopt when it is false at the last step (or the log is empty).
std::optional<double> final_run_start(const EpisodeLog& log, size_t index);

// ISO/TS 15066 protective separation distance S_p (m) for closest-point approach speed v_r
// (m/s, toward the human; negative values count as 0) at separation d (m).
double protective_separation(double approach_speed, double separation, const MetricConstants& c);

// All metrics of one episode. Throws core::InputError if the log is inconsistent
// (check_episode_log), or the contract names a predicate series the log lacks (success,
// intent/contradicted when contradiction is set) or a robot act twice.
EpisodeMetrics compute_metrics(const ScenarioContract& contract, const EpisodeLog& log,
                               const MetricConstants& c = {});

}  // namespace hribench::eval
