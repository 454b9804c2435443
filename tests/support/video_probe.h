#pragma once
// What Debian's ffprobe (package ffmpeg) reads from a video file, for tests of the mp4s we write
// (docs/videos.md, docs/datasets.md): an independent reader, not our own code.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

#include "support/run_command.h"

namespace hribench::testing {

struct VideoProbe {
  std::string codec;      // "h264"
  std::string pix_fmt;    // "yuv420p"
  int width = 0;
  int height = 0;
  int64_t frames = 0;     // frames decoded (ffprobe -count_frames)
  std::string frame_rate; // r_frame_rate, e.g. "20/1"
  double duration = 0;    // s, the stream's
};

// Probes the first video stream of `path`; a failed probe fails the calling test.
inline VideoProbe probe_video(const std::string& path) {
  const CommandResult probe = run_shell(
      "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
      "stream=codec_name,pix_fmt,width,height,nb_read_frames,r_frame_rate,duration -of json '" +
      path + "'");
  VideoProbe video;
  EXPECT_EQ(probe.exit_code, 0) << "ffprobe (Debian's ffmpeg; scripts/install-deps.sh) on " << path
                                << ": " << probe.output;
  if (probe.exit_code != 0) return video;
  const auto stream = nlohmann::json::parse(probe.output).at("streams").at(0);
  video.codec = stream.at("codec_name").get<std::string>();
  video.pix_fmt = stream.at("pix_fmt").get<std::string>();
  video.width = stream.at("width").get<int>();
  video.height = stream.at("height").get<int>();
  video.frames = std::stoll(stream.at("nb_read_frames").get<std::string>());
  video.frame_rate = stream.at("r_frame_rate").get<std::string>();
  video.duration = std::stod(stream.at("duration").get<std::string>());
  return video;
}

// Frame `index` of `path` decoded by ffmpeg to RGB24 bytes (height x width x 3, top row first).
inline std::string decode_frame_rgb(const std::string& path, int64_t index) {
  const CommandResult decoded = run_shell(
      "ffmpeg -v quiet -i '" + path + "' -vf 'select=eq(n\\," + std::to_string(index) +
      ")' -frames:v 1 -f rawvideo -pix_fmt rgb24 -");
  EXPECT_EQ(decoded.exit_code, 0) << "ffmpeg could not decode frame " << index << " of " << path;
  return decoded.output;
}

}  // namespace hribench::testing
