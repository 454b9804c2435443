#include "eval/task_episode.h"

#include "eval/episode.h"

namespace hribench::eval {

namespace {

ScoredEpisode run_observed(Episode& episode, policy::Policy& policy, const std::vector<EpisodeObserver*>& observers) {
  for (EpisodeObserver* observer : observers) episode.add_observer(*observer);
  run_episode(episode, policy);
  return {episode.log(), episode.metrics()};
}

}  // namespace

ScoredEpisode run_task_episode(const script::EpisodeSpec& spec, policy::Policy& policy,
                               const EpisodeSetup& setup, RunOptions options,
                               const std::vector<EpisodeObserver*>& observers) {
  Episode episode(spec, policy.spec(), setup, std::move(options));
  return run_observed(episode, policy, observers);
}

ScoredEpisode run_task_episode(EpisodeScene& scene, policy::Policy& policy, const EpisodeSetup& setup,
                               RunOptions options, const std::vector<EpisodeObserver*>& observers) {
  Episode episode(scene, policy.spec(), setup, std::move(options));
  return run_observed(episode, policy, observers);
}

}  // namespace hribench::eval
