#pragma once
// The round trip of a dataset (docs/datasets.md "Replay"): a recorded episode's actions,
// executed again on its EpisodeSpec, reproduce the episode's log bit for bit (the collector
// executes float32 actions, io/collect.h, so the dataset holds exactly what was executed).
// `hribench replay --dataset DIR` replays every episode of a collect and compares each log
// with the one the collect saved (DIR/hribench/logs).

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "eval/episode_log.h"
#include "policy/policy.h"
#include "script/scenario.h"

namespace hribench::io {

// One episode as a dataset holds it: its identity and the actions executed, one per control
// step (the frames but the last).
struct RecordedEpisode {
  std::string task;
  std::string spec_hash;
  uint64_t seed = 0;
  std::string policy;  // the reference of the policy that produced the actions
  policy::ActionSpace action_space = policy::ActionSpace::kEeDelta;
  std::vector<std::vector<float>> actions;
};

// The recorded episodes of a collect's dataset in DIR, in dataset order, read back from its
// files by the format DIR/hribench/collect.json names. Throws core::InputError for a folder
// that is not a collect, a format without a reader, or files that do not hold what is expected.
std::vector<RecordedEpisode> read_recorded_episodes(const std::filesystem::path& dir);

// Executes `recorded`'s actions on `spec` (an episode of the recorded policy's name, the
// collect's options: the script's horizon, no latency) and returns its log. Throws
// core::InputError when the spec is not the recorded one (hash), an action does not fit the
// episode, or the episode ends before the actions run out or after.
eval::EpisodeLog replay_episode(const script::EpisodeSpec& spec, const RecordedEpisode& recorded);

struct ReplayReport {
  size_t episodes = 0;   // replayed
  size_t identical = 0;  // whose log equals the collect's, bit for bit
  std::vector<std::string> differing;  // "TASK seed SEED: why"
};

// Replays every episode of the collect in DIR (its pool's specs, found by hash) and compares
// each log with DIR/hribench/logs. `limit` > 0: the first `limit` episodes only. Throws
// core::InputError for a dataset recorded in another action space than its policy's own
// (--action-space joint_pos of an ee_delta policy: not the executed actions).
ReplayReport replay_dataset(const std::filesystem::path& dir, size_t limit = 0);

}  // namespace hribench::io
