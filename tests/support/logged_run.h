#pragma once
// A short evaluation run with its episode logs saved (gen::run_evaluation, --save-logs), for
// tests of what reads a run's logs back (gen::load_logged_episode, videos, replays).

#include <filesystem>
#include <string>

#include "gen/evaluation.h"
#include "policy/registry.h"
#include "support/test_files.h"

namespace hribench::testing {

// Runs `policies` on `tasks` for `episodes` sampled seeds from `seed`, each `horizon` s long,
// into a fresh folder named after `name`; returns the folder.
inline std::filesystem::path make_logged_run(const std::string& name, const std::string& tasks,
                                             const std::string& policies, int episodes,
                                             uint64_t seed, double horizon) {
  gen::EvalRequest request;
  request.tasks = tasks;
  request.policies = policies;
  request.episodes = episodes;
  request.seed = seed;
  request.sampling_flags = true;
  request.horizon = horizon;
  request.save_logs = true;
  request.out = temp_dir("logged_run", name);
  gen::run_evaluation(request, [](const std::string& r) { return policy::make_policy(r); });
  return request.out;
}

}  // namespace hribench::testing
