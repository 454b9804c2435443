#pragma once
// H.264 video files (docs/videos.md, docs/datasets.md): RGB frames in, an mp4 out, through
// Debian's libavcodec/libavformat with libx264, pixel format yuv420p (decodes everywhere).
// Frame i is shown at time i / fps exactly (constant frame rate, timestamps 0, 1, 2, ... in a
// 1/fps time base), so a reader seeking to frame_index / fps finds frame frame_index.
//
// The file is written to a temporary name beside `path` and renamed over `path` by finish();
// a writer destroyed without finish() removes its temporary file and leaves `path` untouched.
// One writer is used by one thread; writers on different threads are independent.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "render/image.h"

namespace hribench::io {

struct VideoSettings {
  int fps = 20;               // frames per second, >= 1 (a whole number: datasets need one)
  int crf = 23;               // x264 constant rate factor, 0 (lossless luma) .. 51
  std::string preset = "veryfast";  // x264 preset (speed against size)
  int gop = 20;               // frames between key frames (seeking cost), >= 1
};

class VideoWriter {
 public:
  // Throws core::InputError for a width or height that is not even and positive (yuv420p),
  // fps/crf/gop out of range, an unknown preset, or a file that cannot be opened (where the
  // path).
  VideoWriter(std::filesystem::path path, int width, int height, VideoSettings settings = {});
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  int width() const;
  int height() const;
  const VideoSettings& settings() const;
  const std::filesystem::path& path() const;
  // Frames added so far.
  int64_t frames() const;

  // Appends one frame: an RGB image of exactly width x height (else core::InputError).
  void add(const render::Image& frame);
  // Flushes the encoder, writes the trailer and renames the file into place. Throws
  // core::InputError when nothing was added or the file cannot be written. Called once.
  void finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Encoder identification recorded in results and dataset metadata, e.g.
// "libavcodec 59.37.100 libx264".
std::string video_encoder_version();

}  // namespace hribench::io
