#pragma once
// HDF5 datasets (docs/datasets.md "ACT" and "robomimic") through Debian's libhdf5 (serial, not
// thread-safe: every HDF5 call of this program goes through one process-wide mutex). Images
// are stored gzip-compressed (HDF5's deflate filter, one chunk per frame: (1, H, W, 3)),
// compressed outside the mutex and written as whole chunks, so workers only queue for the file
// write itself. Readers (h5py, ACT's and robomimic's loaders) decompress transparently.
// Objects carry no creation times: the same episodes give the same bytes, whatever the thread
// count of the collect.
//
// ACT (tonyzhaozh/act, record_sim_episodes.py / utils.py):
//   DIR/TASK/episode_0.hdf5, episode_1.hdf5, ... (per task, in commit order, no zero padding)
//   /observations/qpos (T, dof+1) float32   joint_pos + gripper.opening (0 closed .. 1 open)
//   /observations/qvel (T, dof+1) float32   joint_vel + gripper.opening_rate
//   /observations/images/CAM (T, H, W, 3) uint8
//   /observations/state (T, S) float32      the whole Frame::state (attribute names)
//   /action (T, A) float32
//   /annotations/human_act, /annotations/events (T,) UTF-8 strings; /annotations/reward (T,)
//   root attributes: sim = True, and the episode's identity and outcome (task, spec_hash, seed,
//   policy, instruction, success, failure_labels, ...), frames (the recorded frames) and
//   padded_frames.
//   T is the task's max_frames for every episode of the task (ACT stacks whole episodes): an
//   episode that ended earlier is padded by holding its final frame (state, images and held
//   action repeated), rows frames .. T-1.
// robomimic (robomimic docs/datasets/overview.md, dataset_states_to_obs.py):
//   DIR/dataset.hdf5: /data (attributes total, env_args JSON: env_name "HRIBench", type 2,
//   env_version, env_kwargs with action_scale), /data/demo_N (N = 0, 1, ... in commit order;
//   attributes num_samples and the episode's identity and outcome, ep_meta JSON with "lang")
//   holding, for the frames' N - 1 transitions: obs/CAM_image (n, H, W, 3) uint8,
//   obs/GROUP (n, d) float32 per state group, next_obs/... (the next frame's), actions (n, A)
//   float32 = action / action_scale in [-1, 1] (action_scale: per dimension the power of two
//   at least the bound, so the division is exact), rewards (n,) float64, dones (n,) int64,
//   states (n, 1 + nq + nv) float64 (Frame::sim_state); /mask/TASK the demos of each task.
//   Episodes are written to DIR/hribench/robomimic/demo_N.hdf5 as they are committed and
//   copied into dataset.hdf5 by finish().

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "io/recording.h"
#include "io/replay.h"

namespace hribench::io {

class ActWriter : public DatasetWriter {
 public:
  explicit ActWriter(std::filesystem::path dir);
  std::unique_ptr<EpisodeSink> begin_episode(const EpisodeHeader& header) override;
  void commit(std::unique_ptr<EpisodeSink> sink, const EpisodeOutcome& outcome) override;
  void discard(std::unique_ptr<EpisodeSink> sink) override;
  void finish() override {}
  void resume(const std::vector<EpisodeHeader>& committed) override;
  void store(std::unique_ptr<EpisodeSink> sink, const std::filesystem::path& folder) override;
  std::unique_ptr<EpisodeSink> load(const std::filesystem::path& folder) override;

 private:
  std::filesystem::path dir_;
  std::map<std::string, int64_t> episodes_;  // committed per task
};

class RobomimicWriter : public DatasetWriter {
 public:
  explicit RobomimicWriter(std::filesystem::path dir);
  std::unique_ptr<EpisodeSink> begin_episode(const EpisodeHeader& header) override;
  void commit(std::unique_ptr<EpisodeSink> sink, const EpisodeOutcome& outcome) override;
  void discard(std::unique_ptr<EpisodeSink> sink) override;
  void finish() override;
  void resume(const std::vector<EpisodeHeader>& committed) override;
  void store(std::unique_ptr<EpisodeSink> sink, const std::filesystem::path& folder) override;
  std::unique_ptr<EpisodeSink> load(const std::filesystem::path& folder) override;

 private:
  std::filesystem::path dir_;
  std::vector<std::string> tasks_;  // of each committed demo
  std::vector<float> action_scale_;
  std::string action_space_;
  std::vector<std::string> action_names_;
};

// The ACT dataset file name of episode `index` of a task: DIR/TASK/episode_INDEX.hdf5.
std::filesystem::path act_episode_path(const std::filesystem::path& dir, const std::string& task, int64_t index);
// DIR/dataset.hdf5.
std::filesystem::path robomimic_dataset_path(const std::filesystem::path& dir);
// The per-dimension action_scale of robomimic's normalised actions for bounds [low, high].
std::vector<float> robomimic_action_scale(const std::vector<float>& low, const std::vector<float>& high);

// Reads back the recorded episodes (io/replay.h) of an ACT dataset's tasks, in that order, and
// of a robomimic dataset. Throw core::InputError for a missing or malformed file.
std::vector<RecordedEpisode> read_act_episodes(const std::filesystem::path& dir, const std::vector<std::string>& tasks);
std::vector<RecordedEpisode> read_robomimic_episodes(const std::filesystem::path& dir);

}  // namespace hribench::io
