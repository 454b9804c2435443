#pragma once
// One seeded episode of a task file, run and scored as `hribench eval` does (run_task_episode
// with the script's horizon): the per-task tests' common step.

#include <cstdint>
#include <memory>
#include <string>

#include "eval/episode.h"
#include "eval/reward.h"
#include "eval/runner.h"
#include "eval/task_episode.h"
#include "policy/registry.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::eval::testing {

// `task_file` sampled at `seed`, with `policy_ref`, as `hribench eval` sets it up (the script's
// horizon).
struct TaskEpisode {
  script::EpisodeSpec spec;
  std::unique_ptr<policy::Policy> policy;
  EpisodeSetup setup;
  RunOptions options;
};
inline TaskEpisode task_episode(const std::string& task_file, uint64_t seed, const std::string& policy_ref) {
  TaskEpisode t{script::sample(script::load_scenario(task_file), seed), policy::make_policy(policy_ref), {}, {}};
  t.setup = {t.spec.task, t.spec.role, "", t.spec.seed, t.spec.instruction, policy_ref};
  t.options.horizon = 0;  // the script's
  return t;
}

// Samples `task_file` at `seed`, runs `policy_ref` on it and scores it.
inline ScoredEpisode run_task(const std::string& task_file, uint64_t seed, const std::string& policy_ref) {
  TaskEpisode t = task_episode(task_file, seed, policy_ref);
  return run_task_episode(t.spec, *t.policy, t.setup, t.options);
}

// run_task with the episode's dense return (eval/reward.h, the script's weights) beside it.
struct RewardedEpisode {
  ScoredEpisode scored;
  RewardTerms dense_return;
};
inline RewardedEpisode run_task_rewarded(const std::string& task_file, uint64_t seed,
                                         const std::string& policy_ref) {
  TaskEpisode t = task_episode(task_file, seed, policy_ref);
  Episode episode(t.spec, t.policy->spec(), t.setup, t.options);
  run_episode(episode, *t.policy);
  return {{episode.log(), episode.metrics()},
          dense_return(*episode.contract(), episode.log(), t.spec.reward.value_or(script::RewardWeights{}),
                       t.options.constants)};
}

}  // namespace hribench::eval::testing
