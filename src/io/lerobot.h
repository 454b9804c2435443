#pragma once
// LeRobot datasets (docs/datasets.md): the DatasetWriter of `hribench collect --format lerobot`
// (v2.1, read by openpi and GR00T, with GR00T's meta/modality.json) and `--format lerobot-v3`
// (v3.0, read by current LeRobot). Frames go to Parquet tables (io/parquet.h), camera images to
// H.264 mp4s (io/video.h), one row and one video frame per control step.
//
// Crash safety. v2.1: each commit writes the episode's parquet and mp4s, then rewrites every
// meta file (each one atomically), so after any commit the meta files describe exactly the
// episodes on disk. v3.0: committed episodes gather in an open "file group" (one data parquet and
// one mp4 per camera, the episodes' encoded videos re-muxed one after the other, no re-encoding);
// the group is written, then the meta files, when it would pass data_file_size_mb or
// video_file_size_mb, when it holds episodes_per_file episodes, and at finish(). Files are never
// rewritten. A run that stops keeps every episode of the written groups; those of the open group
// are lost and `--resume` collects them again. An episode in progress (not committed) leaves
// nothing. Files go to temporary names renamed when complete; the encoders' staging files live in
// DIR/.staging/ until their episode is placed, and finish() removes the folder.
//
// Resume: LeRobotOptions::resume opens a dataset written with the same version and options,
// keeps its episodes (existing_episodes() lists them) and appends after them; files on disk that
// the meta files do not describe (a run stopped between a file and its meta) are removed first.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string_view>

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
  bool resume = false;               // continue the dataset in `dir` (see above)
};

// A writer of a LeRobot dataset in `dir` (created when missing). Throws core::InputError for
// options out of range, a `dir` holding a LeRobot dataset without `resume`, or with `resume` one
// of another version or options (where the meta file, expected / got).
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

}  // namespace hribench::io
