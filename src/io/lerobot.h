#pragma once
// LeRobot datasets (docs/datasets.md): the DatasetWriter of `hribench collect --format lerobot`
// (v2.1, read by openpi and GR00T, with GR00T's meta/modality.json) and `--format lerobot-v3`
// (v3.0, read by current LeRobot). Frames go to Parquet tables (io/parquet.h), camera images to
// H.264 mp4s (io/video.h), one row and one video frame per control step.
//
// Crash safety. v2.1: each commit writes the episode's parquet and mp4s, then rewrites every
// meta file (each one atomically), so after any commit the meta files describe exactly the
// episodes on disk. v3.0: committed episodes gather in an open "file group" (one data parquet and
// one mp4 per camera, the episodes' encoded videos re-muxed one after the other, no re-encoding).
// Until the group is written each committed episode waits, complete, in DIR/.staging/ (its rows,
// its mp4s and its record). A full group (past data_file_size_mb or video_file_size_mb, or
// holding episodes_per_file episodes) is written, then the meta files, when the next episode is
// committed, and the last one at finish(); written files are never rewritten. An episode in
// progress or discarded leaves nothing. Files go to temporary names renamed when complete;
// finish() removes DIR/.staging/.
//
// Resume (DatasetWriter::resume, --resume): the writer opens the dataset in `dir` (same version,
// chunks_size and file sizes, else core::InputError naming meta/info.json's key), checks that its
// episodes start with the collector's committed ones (spec hash and seed, in order), drops those
// after them (an episode committed just before the run stopped, not recorded by the collector;
// v3.0 drops only staged ones, an error for episodes of a written group), removes the files the meta files do not list (a run stopped between a file and its meta) and
// appends after them. Without resume, the first episode refuses a folder holding a dataset.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "io/recording.h"
#include "io/video.h"

namespace hribench::io {

enum class LeRobotVersion { kV21, kV30 };
// "v2.1", "v3.0": meta/info.json's codebase_version.
std::string_view to_string(LeRobotVersion version);

struct LeRobotOptions {
  VideoSettings video;               // crf, preset, gop; fps comes from the episodes' headers
  int64_t chunks_size = 1000;        // files per chunk folder, >= 1
  int64_t data_file_size_mb = 100;   // v3.0: a data parquet rolls over past this size, >= 1
  int64_t video_file_size_mb = 200;  // v3.0: an mp4 rolls over past this size, >= 1
  int64_t episodes_per_file = 50;    // v3.0: and after this many episodes, >= 1
};

// A writer of a LeRobot dataset in `dir` (created when missing; nothing is read or written before
// resume() or the first episode). Throws core::InputError for options out of range.
//
// Every episode of a dataset has the same fps, robot, state and action names and cameras (the
// first one's, or the resumed dataset's features): begin_episode throws core::InputError for
// another. EpisodeSink::add throws core::InputError for a frame whose index is not the next one,
// whose state or action has another length than the header's names, or whose images are not one
// per camera of the camera's size. commit throws core::InputError for an episode without frames
// or whose outcome counts other frames than were added, and for a file that cannot be written.
std::unique_ptr<DatasetWriter> make_lerobot_writer(const std::filesystem::path& dir,
                                                   LeRobotVersion version,
                                                   const LeRobotOptions& options = {});

// One episode of a LeRobot dataset as read back (for `hribench replay` of a dataset): its
// HRIBench annotations and its rows' vectors.
struct LeRobotEpisode {
  int64_t index = 0;
  std::string instruction;
  std::string task, task_id, role, spec_hash, variant, policy, action_space, status;
  uint64_t seed = 0;
  bool success = false;
  std::vector<std::string> failure_labels;
  std::vector<std::vector<float>> states;   // one per frame (row), observation.state
  std::vector<std::vector<float>> actions;  // one per frame (row), action
};

// The episodes of the LeRobot dataset in `dir` (v2.1 or v3.0, as meta/info.json says), in
// order: those its meta files list. Throws core::InputError for a folder without a dataset,
// files that are missing or do not hold the listed rows.
std::vector<LeRobotEpisode> read_lerobot_episodes(const std::filesystem::path& dir);

}  // namespace hribench::io
