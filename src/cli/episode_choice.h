#pragma once
// The episodes of a run that a per-episode command (`hribench video`, `hribench replay-html`)
// makes its file for: one EPISODE (a log stem of RUN/logs or a .hlog path), or `--failures N`,
// the first N failed episodes with a saved log of each task and policy
// (eval::first_failed_logged_stems over RUN/results.json; docs/report.md).

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace hribench::cli {

struct EpisodeChoice {
  std::string episode;  // EPISODE, "" when not given
  std::optional<int> failures;  // --failures N
};

// Adds the optional positional EPISODE and --failures N to `app`.
void add_episode_choice(CLI::App& app, EpisodeChoice& choice);

// The chosen episodes of `run`: {EPISODE} as given, or the stems --failures picks (possibly
// none). Throws core::InputError when both or neither are given, for N < 1, and for `--out`
// (`out` non-empty) with --failures, which makes several files.
std::vector<std::string> chosen_episodes(const std::string& run, const EpisodeChoice& choice,
                                         const std::string& out);

}  // namespace hribench::cli
