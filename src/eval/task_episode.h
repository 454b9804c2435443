#pragma once
// One episode of a sampled task, run and scored: the path every script-driven evaluation takes
// (hribench eval, the generator's executability filter, the per-task tests). An Episode of the
// spec (eval/episode.h: its scene's model, a ScriptDriver), run by run_episode and scored
// against the full contract of the episode (contract_from_episode: goal positions, permitted
// contacts and waits included).

#include <vector>

#include "eval/episode.h"
#include "eval/episode_log.h"
#include "eval/metrics.h"
#include "eval/runner.h"
#include "policy/policy.h"
#include "script/scenario.h"

namespace hribench::eval {

struct ScoredEpisode {
  EpisodeLog log;
  EpisodeMetrics metrics;
};

// `setup` names the episode in the log; options.horizon <= 0 means the script's horizon.
// Throws core::InputError when the model cannot build the scene or the script does not compile
// (tier 2); trouble inside the episode is the log's status (tier 3). `observers` are called
// as the episode runs (e.g. a LogFileWriter).
ScoredEpisode run_task_episode(const script::EpisodeSpec& spec, policy::Policy& policy,
                               const EpisodeSetup& setup, RunOptions options,
                               const std::vector<EpisodeObserver*>& observers = {});
// The same in `scene` (its Data and renderers; eval/episode.h EpisodeScene): the same log and
// metrics, bit for bit.
ScoredEpisode run_task_episode(EpisodeScene& scene, policy::Policy& policy, const EpisodeSetup& setup,
                               RunOptions options, const std::vector<EpisodeObserver*>& observers = {});

}  // namespace hribench::eval
