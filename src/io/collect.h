#pragma once
// `hribench collect` (docs/datasets.md): rolls a policy out on every episode of a pool's split
// through eval::Episode, renders the cameras at every control step with an observer
// (FrameRecorder: the episode itself is never changed by it) and streams one Frame per control
// step into a DatasetWriter (io/recording.h) of the asked format.
//
// Threads: episodes run on worker threads (one policy, and per episode one renderer per
// camera on the worker's GL context); the main thread commits them to the writer in split
// order, so the dataset is the same for any thread count.
//
// Exact actions: datasets store float32, so the policy runs wrapped in Float32Actions, which
// rounds every action to float32 (to the nearest float inside the action limits) before the
// episode executes it. The recorded action is therefore exactly the executed one, and replaying
// it (io/replay.h) reproduces the episode's log bit for bit. The float32 rounding is the only
// difference from `hribench eval` with the same policy (well under the actuators' resolution).
//
// Shards and ranks (docs/scale.md): with --shard i/N only every N-th episode of the split is
// recorded, and each kept one is stored (DatasetWriter::store) in DIR/hribench/episodes/ instead
// of committed: merge_collect commits the shards' stored episodes in split order into the dataset
// one collect writes. Under mpirun, ranks 1..N-1 run the episodes and store the kept ones there;
// rank 0 loads and commits them in split order as they come (eval/ranks.h).
//
// DIR/hribench/ holds the collector's own files: collect.json (the options and every finished
// episode with its fate, rewritten atomically after each one, so --resume redoes nothing and
// duplicates nothing) and logs/ (each kept episode's log, eval/episode_log.h, the proof a
// replay is compared with).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "eval/episode.h"
#include "gen/pool.h"
#include "io/recording.h"
#include "model/robot.h"
#include "policy/policy.h"
#include "render/gl_context.h"
#include "render/renderer.h"
#include "script/scenario.h"

namespace hribench::io {

// The dataset formats, by --format name: "act-hdf5", "robomimic" (io/hdf5.h), and the LeRobot
// formats where built in.
std::vector<std::string> dataset_format_names();
// A writer of `format` into `dir`; throws core::InputError (where "--format") for an unknown
// format, listing the known ones.
std::unique_ptr<DatasetWriter> make_dataset_writer(std::string_view format, const std::filesystem::path& dir);

// Frame::state of a robot, GROUP.PART names (docs/datasets.md "Features"):
//   joint_pos.<joint>    arm joint positions, rad (one per arm joint, base to tip)
//   joint_vel.<joint>    arm joint velocities, rad/s
//   gripper.opening      finger opening as a fraction of the full opening (0 closed, 1 open)
//   gripper.opening_rate its rate of change, 1/s
//   tcp_pos.x|y|z        tool centre point position in the world frame, m
//   tcp_quat.w|x|y|z     its orientation in the world frame (unit quaternion)
std::vector<std::string> state_names(const model::Robot& robot);
// Frame::action in `space`: ee_delta.dx|dy|dz (m) ee_delta.drx|dry|drz (rad, world frame)
// or joint_target.<joint> (rad), then gripper.opening (fraction), as policy/policy.h's spaces.
std::vector<std::string> action_names(policy::ActionSpace space, const model::Robot& robot);

// `action` rounded to float32 values: each the nearest float, or its neighbour toward the
// double when the nearest lies outside `limits` (validate_chunk's bounds) and the double does not.
std::vector<float> float32_action(const policy::Action& action, policy::ActionSpace space,
                                  const policy::ActionLimits& limits);

// Runs `inner` with every action rounded by float32_action (limits of the episode's robot).
class Float32Actions : public policy::Policy {
 public:
  explicit Float32Actions(std::unique_ptr<policy::Policy> inner);
  policy::PolicySpec spec() const override { return spec_; }
  void reset(const policy::EpisodeInfo& info) override;
  policy::ActionChunk act(const policy::Observation& observation) override;

 private:
  std::unique_ptr<policy::Policy> inner_;
  policy::PolicySpec spec_;
  policy::ActionLimits limits_;
};

// The header of an episode of `spec` recorded with `cameras` (names) at `size` pixels square,
// actions in `action_space` by policy `policy` on `robot`.
EpisodeHeader episode_header(const script::EpisodeSpec& spec, std::string task_id, const std::string& policy,
                             const model::Robot& robot, policy::ActionSpace action_space,
                             const std::vector<std::string>& cameras, int size, double control_dt);

// Observes an episode and adds one Frame per control step to `sink`: frame k is step k of the
// log, with the cameras rendered from the episode's state at that step (a renderer per camera
// made on the calling thread, for the episode's model), and the action executed after it (the
// log's step k + 1; the last frame holds the command in force). Frames are added as soon as
// their action is known (one step late). An exception from the sink propagates out of the
// episode's step and is remembered (sink_failed()). Renders nothing else and changes nothing.
class FrameRecorder : public eval::EpisodeObserver {
 public:
  // Throws core::InputError for a camera `header` names that the model lacks, and as
  // render::make_renderer.
  FrameRecorder(const eval::Episode& episode, const EpisodeHeader& header, EpisodeSink& sink,
                render::Backend backend);
  void on_step(const eval::Episode& episode, const eval::StepRecord& step) override;
  void on_end(const eval::Episode& episode) override;
  int64_t frames() const { return frames_; }
  bool sink_failed() const { return sink_failed_; }

 private:
  void add(Frame& frame);
  const EpisodeHeader& header_;
  EpisodeSink& sink_;
  policy::ActionSpace space_;
  policy::ActionLimits limits_;
  std::vector<std::unique_ptr<render::Renderer>> renderers_;
  std::vector<int> camera_ids_;
  std::vector<render::Image> images_;  // the pending frame's (added before the next is rendered)
  Frame pending_;
  bool has_pending_ = false;
  size_t events_seen_ = 0;
  std::vector<std::string> human_acts_;  // running human acts
  int64_t frames_ = 0;
  bool sink_failed_ = false;
};

struct CollectRequest {
  std::string pool = gen::released_pool();  // --pool
  std::string split = "adapt";           // --split
  std::string policy = "oracle";         // --policy
  std::string cameras = "agentview,wrist";  // --cameras, comma-separated
  int size = 224;                        // --size, pixels (square images)
  std::string format;                    // --format
  std::string out;                       // --out
  std::string tasks = "all";             // --tasks
  int episodes = 0;                      // --episodes: the first N of the split per task; 0: all
  int threads = 1;                       // --threads
  bool resume = false;                   // --resume
  bool force = false;                    // --force
  std::string keep = "success";          // --keep success|all
  std::string action_space;              // --action-space; "": the policy's own
  std::string backend = "osmesa";        // --backend
  bool dry_run = false;  // --dry-run: render every frame, write nothing (no --out, no --format)
  std::string shard;     // --shard i/N: this shard's episodes, stored for `hribench merge`; "": all
};

struct CollectProgress {
  size_t done = 0;      // episodes finished (resumed ones included)
  size_t total = 0;
  size_t resumed = 0;
  size_t kept = 0;      // committed to the dataset (resumed ones included)
  int64_t frames = 0;   // frames recorded in this session
  double frames_per_second = 0;
  double eta = 0;       // s
};

struct CollectSummary {
  size_t episodes = 0;  // of the plan
  size_t kept = 0;      // in the dataset
  size_t resumed = 0;   // finished before this session
  int64_t frames = 0;   // recorded in this session (kept or not)
  double seconds = 0;   // this session's wall time
};

using WriterMaker = std::function<std::unique_ptr<DatasetWriter>(const std::filesystem::path& dir)>;

// Runs the request. Throws core::InputError, before anything is written, for bad options
// (where = the flag: an unknown split, policy, format, action space or camera, a folder holding
// something else, or another collect without --resume/--force, or resumed with other options:
// the differences named); and, after committing every episode before it, for an episode that
// could not be written (it is discarded; the dataset's files describe the committed ones).
// `make` replaces make_dataset_writer (tests inject faults with it).
CollectSummary collect(const CollectRequest& request,
                       const std::function<void(const CollectProgress&)>& progress = nullptr,
                       const WriterMaker& make = nullptr);

// Whether DIR holds a collect (DIR/hribench/collect.json).
bool holds_collect(const std::filesystem::path& dir);

// `hribench merge OUT SHARD_DIR...` of a sharded collect (collect --shard i/N, docs/scale.md):
// writes into OUT (a new folder: the merge command's staging folder) the dataset and the
// hribench/ files (collect.json, logs) one collect without --shard would have written, byte
// for byte, committing the shards' stored episodes in split order. Throws core::InputError,
// before writing anything, for a folder that is not a finished collect shard, a missing or
// repeated shard, shards with other options (the format, the code that recorded them, ...) or
// a shard that does not hold exactly its episodes; and for stored episodes that cannot be
// read. Returns the merged collect's summary (episodes, kept).
CollectSummary merge_collect(const std::filesystem::path& out, const std::vector<std::string>& dirs);

// DIR/hribench/collect.json of a collect: {"options": {...}, "episodes": [{key, task, seed,
// spec_hash, kept, index (in the dataset, kept ones), success, status, labels, frames}],
// "finished"}; a shard's options add shard, shard_of_jobs, code and backend, and its episodes
// their job number in the full split ("job").
std::filesystem::path collect_state_path(const std::filesystem::path& dir);
// DIR/hribench/logs/ file of a kept episode.
std::filesystem::path collect_log_path(const std::filesystem::path& dir, const std::string& task, uint64_t seed,
                                       const std::string& spec_hash);

}  // namespace hribench::io
