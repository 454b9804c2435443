#pragma once
// The dense training reward (docs/python.md "Rewards"), derived from the script: each term is
// read from the episode log up to the step it rewards and the episode's contract
// (eval/contract.h), so the same log always gives the same rewards. The metrics
// (eval/metrics.h) remain the benchmark's score; rewards are for training.
//
// The reward of step k >= 1 (the control interval (t_{k-1}, t_k]) is the sum of
//   progress          +w * (d_{k-1} - d_k): d = distance (m) from the tool (TCP) to the goal
//                     of the current robot act, the first of the contract's robot acts whose
//                     "ACT.end" event has not happened by t_k (acts without a goal: 0);
//   success           +w once, at the episode's last step, if the episode succeeds by the
//                     metrics (EpisodeMetrics::success, the sparse reward's condition: success
//                     held at the end, every act in order, no premature answer, no critical
//                     contact), so a robot that finishes the task but fails the interaction
//                     earns no bonus;
//   premature_motion  -w * the tool's displacement toward the current act's goal (m; without a
//                     goal, its whole displacement) in a step whose speed toward it exceeds
//                     response_speed (the metrics' onset threshold: slower drift, backing off
//                     and holding are not answers), while the current act answers go cues and
//                     none of them allows motion yet (CueContract::motion_allowed_from, else
//                     the cue's event, has not happened by t_{k-1});
//   separation        -w * dt while the separation is a violation by HCS's rule (docs/metrics.md:
//                     closer than the protective distance, or inside a permitted contact phase
//                     faster than permitted_speed within permitted_distance);
//   contact           -w * dt * grade(region) for each human contact at step k that no
//                     permitted contact covers; grade = the lowest quasi-static force limit of
//                     any region / the region's limit (ISO/TS 15066: head and shin 1, thigh 0.59).
// The weights w are script::RewardWeights: the script's `reward` section, else the defaults.

#include <cstddef>

#include "eval/constants.h"
#include "eval/contract.h"
#include "eval/episode_log.h"
#include "eval/metrics.h"
#include "human/skeleton.h"
#include "script/scenario.h"

namespace hribench::eval {

// One step's reward, term by term (each already weighted and signed).
struct RewardTerms {
  double progress = 0;
  double success = 0;
  double premature_motion = 0;
  double separation = 0;
  double contact = 0;
  double total() const { return progress + success + premature_motion + separation + contact; }
};

// The reward of `log`'s step k (1 <= k < log.steps.size(); HRIB_CHECK), from the steps and
// events up to it. `ended`: the episode's metrics when step k is its last (the episode is
// over), else null; only then is the success term paid.
RewardTerms dense_reward(const ScenarioContract& contract, const EpisodeLog& log, size_t k,
                         const script::RewardWeights& weights, const MetricConstants& constants,
                         const EpisodeMetrics* ended = nullptr);

// The sum of dense_reward over every step of a finished episode's log (the episode's return;
// its metrics are computed for the last step's success term).
RewardTerms dense_return(const ScenarioContract& contract, const EpisodeLog& log,
                         const script::RewardWeights& weights, const MetricConstants& constants);

// A region's contact grade in (0, 1] (the lowest quasi-static limit over its own).
double contact_grade(human::BodyRegion region);

}  // namespace hribench::eval
