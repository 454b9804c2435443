#pragma once
// The episode pool (issue 7): validated episodes of every task, split into `adapt` (policy
// adaptation), `eval` (the held-out evaluation split) and `test` (hidden), and named by a
// versioned manifest.
//
// A pool folder holds:
//   manifest.json          {"pool_version", "generator" (the options that made it),
//                           "episodes": [{task, script, split, candidate, seed, hash}]}
//   report.json, report.md the generation report (gen/generate.h)
//   options.json           the generator options (for --resume)
//   candidates.jsonl       one line per candidate as it was judged (for --resume)
//   episodes/TASK/cNNNN.json  each validated episode spec (script::spec_to_text)
// Only manifest.json and the report are needed to evaluate: an episode is re-sampled from its
// script and seed, and its content hash must equal the manifest's (otherwise the scripts or
// the sampler changed and the pool version must be bumped).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/json.h"
#include "script/scenario.h"

namespace hribench::gen {

// Any change to the pipeline that alters the pool must bump this. 1: pool/v1 (git fae9ab2-
// 47ceb8a); 2: C2's moving receiving hand and the oracle's X1, I2, C2 and C4 fixes (pool/v2,
// git f674cb8-517d527); 3: the oracle's head clearance in handovers, C1's take, X2's lying
// bottles, I5's lowering near a person and the cube's grasp faces (pool/v3, git 89f84a7-
// 6e6b94a); 4: the robot in every spec and manifest, the person's bent-knee lean and fingers,
// the reframed agentview, the at_rest filter and the visibility filter at 224 px (pool/v4,
// git ed22767-7275c5b); 5: the Euler integrator at 2.5 ms with the arm servos' damping in the
// joints and heavier fingers, the person's lean solved every 50 ms, and fingers that move
// against the gripper's command no longer counted as the robot moving (pool/v5, git
// b1bfa23-13a8883); 6: co_lift's success also asks for the robot's share of the lift,
// ever(grasped(robot, plank) and moved(plank, 0.10) and tilt(plank) < 15) (pool/v6, git
// 6c5c89a-ee3b8ce); 7: the 5 ms physics step with 1.2 kg fingers, a hidden square foot under
// every cup and bottle, and each control step's state observed with MuJoCo's kinematics
// instead of a forward pass (pool/v7, git a223241-98a17ce); 8: the person posed from the plans
// once per control step and interpolated between, and a reaching hand's lean solved every
// 100 ms (pool/v8).
inline constexpr int kPoolVersion = 8;
// The released pool of this benchmark version, as a path from the data root: "pool/vN" with N
// = kPoolVersion (docs/generation.md).
std::string released_pool();

enum class Split { kAdapt, kEval, kTest };
std::string_view to_string(Split split);  // "adapt" | "eval" | "test"
// Throws core::InputError (where = `where`) for anything else.
Split split_from_name(std::string_view name, std::string_view where);

// Episodes per task in each split (defaults: issue 7's >= 50 adapt and >= 10 eval, and a hidden
// test split of 5, so that 150 candidates fill every task of the released pool: 65 of the 150
// candidates of someone_else_places validated in pool/v1).
struct SplitSizes {
  size_t adapt = 50;
  size_t eval = 10;
  size_t test = 5;
  size_t total() const { return adapt + eval + test; }
};

// The seed of candidate `index` of `task` in a generation seeded with `seed` (48 bits, so it
// is exact in any JSON reader).
uint64_t candidate_seed(uint64_t seed, std::string_view task, size_t index);

// The split of each of `validated` episodes of a task (in candidate order): a deterministic
// shuffle seeded by (seed, task); the first sizes.adapt go to adapt, the next sizes.eval to
// eval, the rest to test. Requires validated >= sizes.total().
std::vector<Split> assign_splits(size_t validated, uint64_t seed, std::string_view task,
                                 const SplitSizes& sizes);

struct PoolEntry {
  std::string task;    // the scenario's task name, e.g. "point_pick"
  std::string script;  // the script file it was sampled from, e.g. "tasks/I1_point_pick.yaml"
  Split split = Split::kAdapt;
  size_t candidate = 0;
  uint64_t seed = 0;
  std::string hash;    // script::spec_hash
};

struct Manifest {
  int pool_version = kPoolVersion;
  core::Json generator = core::Json::object();  // the options that made the pool
  std::vector<PoolEntry> episodes;  // by task (generator order), then candidate index
};

core::Json to_json(const Manifest& manifest);
// Throws core::InputError (where = "SOURCE (key.path)") for a malformed manifest, a pool
// version this build does not know, a generator without a known robot, or two episodes sharing
// a seed within a task.
Manifest manifest_from_json(const core::Json& json, std::string_view source);
// The robot the pool's episodes were sampled for (generator.robot; manifest_from_json checked
// it names a known robot description).
std::string pool_robot(const Manifest& manifest);
// DIR/manifest.json (DIR relative to the working directory or else to the data root); throws
// core::InputError when missing or malformed.
Manifest read_manifest(const std::string& dir);

// A task of the benchmark, from its script's file name tasks/ID_NAME.yaml: its id (e.g. "I1",
// as docs/tasks.md names tasks), its name (the script's `task`, e.g. "point_pick") and its
// script path as recorded in manifests and options ("tasks/I1_point_pick.yaml", relative to the
// data root of core/paths.h, whatever the working directory).
struct TaskFile {
  std::string id;
  std::string name;
  std::string script;
};
// The scripts of data_root()/tasks, sorted by file name.
std::vector<TaskFile> task_catalogue();
// "I1 point_pick, I2 gesture_delivery, ..." (for messages and help).
std::string task_list_text();

// Task ids (I4), names (stop_go), stems (I4_stop_go), script files, or `all` (every task of
// task_catalogue()), comma-separated -> script paths (catalogue tasks as TaskFile::script, files
// as given). Throws core::InputError (where = "--tasks") for a name that matches nothing (the
// message lists every id and name) or an empty list.
std::vector<std::string> resolve_task_scripts(const std::string& list);

// The episodes of `split` (all tasks, or those matching one of `tasks` by task name, script
// file, or script stem, its prefix or suffix), re-sampled from their scripts (paths relative to
// the working directory or else to the data root, core::resolve_data_path) and checked against the manifest hashes. Throws core::InputError
// (where "--tasks") for a name that matches no task of the pool, when a script is missing or
// fails check, or when an episode's hash differs ("the pool was made by other scripts").
std::vector<script::EpisodeSpec> pool_episodes(const Manifest& manifest, Split split,
                                               const std::vector<std::string>& tasks = {});

}  // namespace hribench::gen
