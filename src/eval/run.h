#pragma once
// An evaluation run (docs/metrics.md "Results"): every (task, policy, episode) job run on
// worker threads, each episode appended to OUT/episodes.jsonl as it finishes (so a resumed run
// loses nothing), and OUT/results.json, summary.md and summary.csv written at the end.
// OUT/options.json records the options that change results; a folder holding another run is
// refused unless resumed (same options; or more episodes, which extends the run with the next
// seeds) or forced, and an episode pool's folder (or a file) is refused outright. The run `hribench eval` and Python's
// hribench.evaluate make (gen/evaluation.h builds the plan from their options).
//
// Under mpirun with several ranks (eval/ranks.h) rank 0 prepares OUT, hands the jobs out to the
// worker threads of the other ranks and writes every file but the logs and videos, which the
// rank that ran the episode writes; the other ranks return no results.
//
// Reuse: each worker thread makes one instance of each policy (PolicyMaker) for the whole run
// and resets it for every episode (Policy::reset), and keeps the EpisodeScene (model, Data,
// renderers; eval/episode.h) of the episode it ran last. Jobs are handed out episode by
// episode, the policies of one episode in a row, so a worker that runs several policies on an
// episode builds its scene once. Results do not depend on it (the same logs, bit for bit).

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "eval/episode.h"
#include "eval/report.h"
#include "eval/shard.h"
#include "policy/policy.h"
#include "script/scenario.h"

namespace hribench::eval {

struct RunPlan {
  std::vector<std::vector<script::EpisodeSpec>> by_task;  // the episodes, grouped by task
  std::vector<std::string> policies;  // policy references, as the results name them
  nlohmann::json options = nlohmann::json::object();  // OUT/options.json (--resume compares it)
  std::map<std::string, std::string> task_ids;  // docs/tasks.md's id of each task by name (I1)
  std::optional<Shard> shard;  // run only this shard's jobs (eval/shard.h); options record it
};

struct RunSettings {
  std::filesystem::path out;
  int threads = 1;         // >= 1
  bool resume = false;     // continue the run in `out` (same options)
  bool force = false;      // replace the run in `out`
  bool save_logs = false;  // OUT/logs/TASK__POLICY__SEED__HASH.hlog per episode
  RunOptions run_options;
  // Episodes whose policy could not be reached (for remote policies remote::is_connect_failure
  // of the status reason); null: none are. After `max_unreachable` of them in a row the run
  // stops with RunStopped; those are held back, not written, so a resumed run runs them again
  // (docs/remote-policies.md). An isolated one is written once a later episode reaches it.
  std::function<bool(const EpisodeResult&)> unreachable;
  int max_unreachable = 3;
  // Called on the worker thread after each episode that ran (its log complete and scored; not
  // for one whose scene could not be built), with the episode's file stem (eval/episode_files.h): e.g.
  // `hribench eval --video` writing OUT/videos/STEM.mp4 from the log. Must not change the
  // episode. An exception from it is printed as a warning and the episode's result stands.
  std::function<void(const script::EpisodeSpec&, const EpisodeLog&, const EpisodeResult&,
                     const std::string& stem)>
      after_episode;
};

// Thrown by run_plan when the policy could not be reached for max_unreachable episodes in a
// row: "N episodes in a row could not connect (REASON); M episodes are in OUT/episodes.jsonl".
class RunStopped : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// After each finished episode: episodes done (resumed ones included) of the run's total.
struct RunProgress {
  size_t done = 0;
  size_t total = 0;
  size_t resumed = 0;
  double rate = 0;  // episodes per second of this session
  double eta = 0;   // s
};

// Makes one policy of a reference of the plan (policy::make_policy for the registry's).
// Called once per worker thread and reference, from that worker's thread.
using PolicyMaker = std::function<std::unique_ptr<policy::Policy>(const std::string& reference)>;

// Runs the plan into settings.out and returns the results in job order (task, policy,
// episode), whatever the completion order, thread count or resume history. Throws
// core::InputError when `out` is a file or a pool, holds another run (neither resume nor
// force, or resumed with other options: the differences named) or cannot be written. An episode's trouble (a scene that cannot be built,
// a policy that fails) is that episode's status, never an exception.
RunResults run_plan(const RunPlan& plan, const RunSettings& settings, const PolicyMaker& make,
                    const std::function<void(const RunProgress&)>& progress = nullptr);

}  // namespace hribench::eval
