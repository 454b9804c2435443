#pragma once
// What a dataset writer receives from `hribench collect` (docs/datasets.md): one recorded
// episode at a time, frame by frame, one frame per control step (20 Hz) from step 0 to the
// episode's last step. The collector runs episodes on worker threads; each worker streams its
// episode into an EpisodeSink made by the writer, and the collector then commits (keeps) or
// discards the sink on the main thread, in the split's order, so episode indices and global
// row numbers follow the split whatever the thread count.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "render/image.h"

namespace hribench::io {

struct CameraSpec {
  std::string name;  // the model's camera name ("agentview", "wrist")
  int width = 0;     // pixels
  int height = 0;
};

// An episode's identity and the meaning of each frame's vectors; fixed for the episode.
struct EpisodeHeader {
  std::string task;         // scenario name ("point_pick")
  std::string task_id;      // docs/tasks.md's id ("I1")
  std::string role;         // the task's role group
  std::string instruction;  // the language instruction (the dataset's task string)
  std::string spec_hash;    // the EpisodeSpec's hash
  uint64_t seed = 0;
  std::string variant;      // the script's variant ("" when it has none)
  std::string policy;       // the policy reference that produced the actions
  std::string robot;        // "panda"
  int fps = 20;             // control rate, frames per second
  // Names are GROUP.PART ("joint_pos.<arm joint>", "gripper.opening"): the dimensions of a
  // group are consecutive, so a group is a slice (GR00T's modality.json, ACT's qpos).
  std::vector<std::string> state_names;   // one per dimension of Frame::state
  std::vector<std::string> action_names;  // one per dimension of Frame::action
  std::string action_space;               // the action space of Frame::action
  std::vector<CameraSpec> cameras;        // aligned with Frame::images
  // Bounds every Frame::action respects, one per action dimension (the episode's action limits).
  std::vector<float> action_low;
  std::vector<float> action_high;
  // The most frames an episode of this task can have (its horizon / control step + 1): formats
  // whose episodes of a task share one length (ACT) pad to it.
  int64_t max_frames = 0;
};

// One control step. Pointers and vectors are valid during EpisodeSink::add only.
struct Frame {
  int64_t index = 0;   // frame index in the episode, 0, 1, 2, ...
  double time = 0;     // simulated time, s (index / fps)
  std::vector<float> state;   // proprioception, header.state_names
  // The action executed from this step on, header.action_names; on the last frame (nothing
  // executed after it) the command in force held (docs/datasets.md).
  std::vector<float> action;
  std::vector<const render::Image*> images;  // one per header.cameras, RGB of its size
  std::string human_act;      // the human act running at this step ("" when none)
  std::vector<std::string> events;  // cue and act events since the previous frame
  float reward = 0;           // the scenario's sparse reward at this step
  bool done = false;          // the last frame of the episode
  // The simulation state at this step, flattened: [time, qpos (nq), qvel (nv)] of the
  // episode's MuJoCo model (robomimic's `states`).
  std::vector<double> sim_state;
};

// How the episode ended.
struct EpisodeOutcome {
  bool success = false;
  core::EpisodeStatus status = core::EpisodeStatus::kOk;
  // docs/metrics.md's labels that apply; a successful episode may carry interaction labels
  // (e.g. desync, unsafe_proximity).
  std::vector<std::string> failure_labels;
  int64_t frames = 0;                       // frames added
};

// Receives one episode's frames on one worker thread.
class EpisodeSink {
 public:
  virtual ~EpisodeSink() = default;
  virtual void add(const Frame& frame) = 0;
};

// One dataset format. begin_episode may be called from any worker thread at once; commit,
// discard and finish are called from the collector's thread only, commits in episode order.
// Everything a writer writes goes to temporary names renamed when complete: a run that stops
// leaves the committed episodes valid and the meta files describing exactly them.
class DatasetWriter {
 public:
  virtual ~DatasetWriter() = default;
  virtual std::unique_ptr<EpisodeSink> begin_episode(const EpisodeHeader& header) = 0;
  // Keeps the episode as the dataset's next one.
  virtual void commit(std::unique_ptr<EpisodeSink> sink, const EpisodeOutcome& outcome) = 0;
  // Drops it (a failed episode without --keep all, or one that went wrong): nothing remains.
  virtual void discard(std::unique_ptr<EpisodeSink> sink) = 0;
  // Writes the dataset-wide files (meta/info.json, stats, ...) for what is committed.
  virtual void finish() = 0;
  // Continuing an interrupted collect (--resume), called once before any begin_episode: the
  // dataset holds exactly `committed` (the headers of the episodes the collector recorded as
  // committed, in commit order); anything written beyond them (an episode committed just before
  // the interruption, but not recorded) is dropped. Throws core::InputError when the files on
  // disk do not hold them. The default refuses to resume a non-empty dataset.
  virtual void resume(const std::vector<EpisodeHeader>& committed);

  // Sharded and MPI collects (docs/scale.md "Sharded collects"): a finished episode (its last
  // frame added) is stored in `folder` (new; store creates it) as the writer's own files,
  // nothing in them depending on the episode's place in a dataset. A writer of the same format,
  // in this or another process, later loads it and commits the sink: the dataset then holds the
  // bytes a commit of the original sink would have written. load copies what it needs (`folder`
  // stays as it is) and throws core::InputError for a folder that holds no episode this format
  // stored. The defaults refuse (a format that cannot be sharded).
  virtual void store(std::unique_ptr<EpisodeSink> sink, const std::filesystem::path& folder);
  virtual std::unique_ptr<EpisodeSink> load(const std::filesystem::path& folder);
};

// An episode's header as JSON (every field; floats exactly, as doubles) and back (throws
// core::InputError, where = `where`, for JSON that is not a header): what store() keeps of it.
nlohmann::json episode_header_json(const EpisodeHeader& header);
EpisodeHeader episode_header_from_json(const nlohmann::json& json, const std::string& where);

}  // namespace hribench::io
