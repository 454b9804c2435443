#pragma once
// One seeded episode of a task file, run and scored as `hribench eval` does (run_task_episode
// with the script's horizon): the per-task tests' common step.

#include <cstdint>
#include <memory>
#include <string>

#include "eval/task_episode.h"
#include "policy/registry.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::eval::testing {

// Samples `task_file` at `seed`, runs `policy_ref` on it and scores it.
inline ScoredEpisode run_task(const std::string& task_file, uint64_t seed, const std::string& policy_ref) {
  const script::EpisodeSpec spec = script::sample(script::load_scenario(task_file), seed);
  std::unique_ptr<policy::Policy> policy = policy::make_policy(policy_ref);
  const EpisodeSetup setup{spec.task, spec.role, "", spec.seed, spec.instruction, policy_ref};
  RunOptions options;
  options.horizon = 0;  // the script's
  return run_task_episode(spec, *policy, setup, options);
}

}  // namespace hribench::eval::testing
