#include "cli/episode_choice.h"

#include "core/errors.h"
#include "eval/episode_files.h"
#include "eval/report.h"

namespace hribench::cli {

void add_episode_choice(CLI::App& app, EpisodeChoice& choice) {
  app.add_option("episode", choice.episode,
                 "The episode: a log stem of RUN/logs (TASK__POLICY__SEED__HASH) or a .hlog file");
  app.add_option("--failures", choice.failures,
                 "Instead of EPISODE: the first N failed episodes with a saved log of each task and policy");
}

std::vector<std::string> chosen_episodes(const std::string& run, const EpisodeChoice& choice,
                                         const std::string& out) {
  if (!choice.failures) {
    if (choice.episode.empty()) {
      throw core::InputError("EPISODE", "a log stem of " + run + "/logs, or --failures N", "neither");
    }
    return {choice.episode};
  }
  if (!choice.episode.empty()) {
    throw core::InputError("--failures", "either EPISODE or --failures N",
                           "both (EPISODE '" + choice.episode + "')");
  }
  if (*choice.failures < 1) {
    throw core::InputError("--failures", "a positive number", std::to_string(*choice.failures));
  }
  if (!out.empty()) {
    throw core::InputError("--out", "one EPISODE (--out names one file)", "--failures, which makes several");
  }
  return eval::first_failed_logged_stems(run, eval::load_run(run).episodes, *choice.failures);
}

}  // namespace hribench::cli
