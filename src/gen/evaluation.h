#pragma once
// An evaluation from its options, as `hribench eval` and Python's hribench.evaluate take them
// (docs/getting-started.md, docs/python.md): the options checked (one-line messages naming
// the CLI flag), the episodes chosen (a pool's split, or each task's script sampled with
// seeds S..S+N-1), and the run (eval/run.h) made.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "eval/episode_log.h"
#include "eval/report.h"
#include "eval/run.h"

namespace hribench::gen {

struct EvalRequest {
  std::string tasks = "all";          // --tasks: names, ids, files, or all
  std::string policies;               // --policy: references, comma-separated
  int episodes = 10;                  // --episodes (sampled seeds)
  uint64_t seed = 0;                  // --seed
  bool sampling_flags = false;        // --episodes or --seed given
  std::string pool;                   // --pool: a pool folder, or empty: sample seeds
  std::string split = "eval";         // --split (with pool)
  int threads = 1;                    // --threads
  std::string latency = "none";       // --latency
  double horizon = -1;                // --horizon, s; -1: each script's own
  std::string out;                    // --out
  bool resume = false;                // --resume
  bool force = false;                 // --force
  bool save_logs = false;             // --save-logs
  std::string shard;                  // --shard i/N, or empty: every job (eval/shard.h)
};

// The items of a comma-separated flag value ("I1,C2"), empty items dropped.
std::vector<std::string> split_list(const std::string& text);

// Checks the request and chooses its episodes; throws core::InputError (where = the flag) for
// contradictory or bad options, an unknown policy (make throws), tasks that match nothing or
// an unusable pool. `make` makes the policies of the request's references.
eval::RunPlan plan_evaluation(const EvalRequest& request, const eval::PolicyMaker& make,
                              eval::RunSettings& settings);

// Tasks whose episodes all ended before their first cue under a `horizon` (s) shorter than
// the script's: their scores say nothing about responding to the person (a warning).
std::vector<std::string> tasks_ended_before_a_cue(const eval::RunPlan& plan,
                                                  const std::vector<eval::EpisodeResult>& episodes,
                                                  double horizon);

// A saved episode of a run (eval --save-logs): its log file and the EpisodeSpec it ran, for
// the commands that show an episode again from its log alone (hribench video, replay-html).
struct LoggedEpisode {
  std::filesystem::path log_file;  // RUN/logs/STEM.hlog
  eval::EpisodeLog log;
  script::EpisodeSpec spec;        // rebuilt from the run's options.json: spec_hash(spec) == log's
};

// `episode` is a log's stem (TASK__POLICY__SEED__HASH, as RUN/logs/ names it) or the path of a
// .hlog file (eval::find_episode_log, where "EPISODE"). Throws core::InputError: RUN not a run
// folder (no options.json), no saved logs ("run eval with --save-logs"), an unknown stem (a few
// that exist are named), a log that does not load, or a spec the run's tasks or pool no longer
// give (the hashes named).
LoggedEpisode load_logged_episode(const std::filesystem::path& run, const std::string& episode);

// plan_evaluation, then eval::run_plan.
eval::RunResults run_evaluation(const EvalRequest& request, const eval::PolicyMaker& make,
                                const std::function<void(const eval::RunProgress&)>& progress = nullptr);

}  // namespace hribench::gen
