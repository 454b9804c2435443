#pragma once
// The generation pipeline (issue 7): sample `candidates` episodes of every task script (seeds
// from gen::candidate_seed), judge each with the filters of gen/filters.h on a thread pool,
// split the validated ones (gen::assign_splits), and write the pool folder (gen/pool.h):
// episode specs, manifest, generation report. Deterministic for any thread count: every
// output is ordered by (task, candidate index), never by completion order, and holds no
// wall-clock time.
//
// Resumable: each judged candidate is appended to OUT/candidates.jsonl as it finishes; with
// `resume` a folder made with the same options continues without judging those again.
//
// Sharded (docs/scale.md): with `shard` i/N only the candidates j of the full list (task, then
// candidate index) with j mod N = i are judged, and the folder keeps options.json (with the
// shard, the job count and the code that judged) and candidates.jsonl, no split and no
// manifest; merge_generation combines the N folders into the pool one process writes.

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/json.h"
#include "eval/shard.h"
#include "gen/filters.h"
#include "gen/pool.h"
#include "model/robot.h"
#include "script/scenario.h"

namespace hribench::gen {

struct GenerateOptions {
  std::vector<std::string> scripts;  // task script files, in report order
  size_t candidates = 150;           // per task
  uint64_t seed = 0;
  std::string robot{model::kDefaultRobot};  // the robot the episodes are sampled for
  int threads = 1;
  SplitSizes splits;
  FilterOptions filters;
  std::string out;                   // the pool folder
  bool resume = false;
  bool progress = true;              // a progress line on stderr
  std::optional<eval::Shard> shard;  // judge only this shard's candidates (see above)
};

// One judged candidate.
struct CandidateRecord {
  std::string task;
  size_t index = 0;
  uint64_t seed = 0;
  std::string hash;
  std::optional<Filter> failed;  // nullopt: validated
  std::string reason;
};
core::Json to_json(const CandidateRecord& record);
CandidateRecord candidate_from_json(const core::Json& json, std::string_view source);

// Counts of one task (or of all tasks).
struct TaskReport {
  std::string task;
  std::string script;
  size_t candidates = 0;
  std::array<size_t, kNumFilters> passed{};  // candidates that passed filter k (and all before)
  std::array<std::string, kNumFilters> example;  // the first rejection reason of filter k
  size_t validated = 0;
  double yield() const { return candidates ? static_cast<double>(validated) / static_cast<double>(candidates) : 0; }
};

struct GenerationReport {
  core::Json generator;            // the options (as in the manifest)
  std::vector<TaskReport> tasks;
  TaskReport total;                // task "all"
};
core::Json to_json(const GenerationReport& report);
// The report table: one row per task, the candidates left after each filter, the yield.
std::string report_markdown(const GenerationReport& report);

// The options that define a pool (written into the manifest and options.json): version,
// seed, robot, candidates, split sizes, executable_by, and each task's name and script.
core::Json generator_json(const GenerateOptions& options, const std::vector<std::string>& task_names);

// Judges one candidate: samples it for `robot` and runs the filters.
CandidateRecord judge_candidate(const script::Scenario& scenario, const std::string& task, size_t index,
                                uint64_t seed, std::string_view robot, const FilterOptions& filters);

// Runs the whole pipeline and writes the pool. Throws core::InputError, writing nothing, for
// a script that fails check, an unknown executable_by policy, candidates < splits.total()
// (naming how many are missing), a bad thread count, or an OUT that holds another pool (a
// manifest, or an unfinished generation with other options, or with the same options without
// `resume`). After judging, a task with fewer validated episodes than the splits need throws
// core::InputError naming each such task and how many are missing; OUT then keeps
// options.json, candidates.jsonl and report.md, and no manifest.
// A shard (options.shard) judges its candidates and returns a report without task rows.
GenerationReport generate(const GenerateOptions& options);

// Whether `dir` holds a generation (its candidates.jsonl), finished or not.
bool holds_generation(const std::string& dir);

// Combines the folders of a sharded generation (`generate --shard i/N`, one per shard, each
// finished) into `out`, a new folder (the merge command's staging folder): the pool one
// `generate` without --shard writes (manifest, specs and reports byte for byte;
// candidates.jsonl in (task, candidate) order).
// Throws core::InputError naming the folder when a folder is not a generation shard, the
// shards do not cover 0..N-1 once each, their options or code differ (eval::shard_order), or
// a shard does not hold exactly its candidates.
GenerationReport merge_generation(const std::string& out, const std::vector<std::string>& dirs);

}  // namespace hribench::gen
