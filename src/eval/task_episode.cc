#include "eval/task_episode.h"

#include "eval/episode.h"

namespace hribench::eval {

ScoredEpisode run_task_episode(const script::EpisodeSpec& spec, policy::Policy& policy,
                               const EpisodeSetup& setup, RunOptions options,
                               const std::vector<EpisodeObserver*>& observers) {
  Episode episode(spec, policy.spec(), setup, std::move(options));
  for (EpisodeObserver* observer : observers) episode.add_observer(*observer);
  run_episode(episode, policy);
  return {episode.log(), episode.metrics()};
}

}  // namespace hribench::eval
