#include "io/video.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "support/test_files.h"
#include "support/video_probe.h"

namespace hribench::io {
namespace {

using testing::decode_frame_rgb;
using testing::error_of;
using testing::probe_video;
using testing::read_text;
using testing::temp_dir;

// A picture that changes with `index`: a bright square moving right on a colour gradient.
render::Image test_frame(int width, int height, int index) {
  render::Image image;
  image.resize(width, height);
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      uint8_t* pixel = &image.rgb[(static_cast<size_t>(row) * static_cast<size_t>(width) +
                                   static_cast<size_t>(col)) * 3];
      const bool square = col >= 4 * index && col < 4 * index + 16 && row >= 8 && row < 24;
      pixel[0] = square ? 250 : static_cast<uint8_t>(4 * col);
      pixel[1] = square ? 250 : static_cast<uint8_t>(5 * row);
      pixel[2] = square ? 250 : 90;
    }
  }
  return image;
}

std::filesystem::path write_test_video(const std::filesystem::path& path, int frames,
                                       VideoSettings settings = {}) {
  VideoWriter writer(path, 64, 48, settings);
  for (int i = 0; i < frames; ++i) writer.add(test_frame(64, 48, i));
  EXPECT_EQ(writer.frames(), frames);
  writer.finish();
  return path;
}

TEST(VideoWriter, WritesH264Yuv420pWithOneFramePerImageAtTheFrameRate) {
  const std::filesystem::path dir = temp_dir("video", "probe");
  std::filesystem::create_directories(dir);
  const auto path = write_test_video(dir / "clip.mp4", 12, {.fps = 20});
  const auto video = probe_video(path.string());
  EXPECT_EQ(video.codec, "h264");
  EXPECT_EQ(video.pix_fmt, "yuv420p");
  EXPECT_EQ(video.width, 64);
  EXPECT_EQ(video.height, 48);
  EXPECT_EQ(video.frames, 12);
  EXPECT_EQ(video.frame_rate, "20/1");
  EXPECT_NEAR(video.duration, 12 / 20.0, 1e-6);
  EXPECT_FALSE(std::filesystem::exists(dir / "clip.mp4.tmp"));
}

TEST(VideoWriter, EachDecodedFrameIsItsImageWithinCompressionTolerance) {
  const std::filesystem::path dir = temp_dir("video", "frames");
  std::filesystem::create_directories(dir);
  const auto path = write_test_video(dir / "clip.mp4", 10, {.crf = 18});
  for (int index : {0, 3, 9}) {
    const std::string decoded = decode_frame_rgb(path.string(), index);
    const render::Image expected = test_frame(64, 48, index);
    ASSERT_EQ(decoded.size(), expected.rgb.size()) << "frame " << index;
    double error = 0;
    for (size_t i = 0; i < decoded.size(); ++i)
      error += std::abs(static_cast<uint8_t>(decoded[i]) - static_cast<int>(expected.rgb[i]));
    EXPECT_LT(error / static_cast<double>(decoded.size()), 6.0) << "frame " << index;
    // The moving square is where frame `index` put it, not where a neighbour did.
    const size_t inside = ((16 * 64) + 4 * static_cast<size_t>(index) + 8) * 3;
    EXPECT_GT(static_cast<uint8_t>(decoded[inside]), 200) << "frame " << index;
  }
}

TEST(VideoWriter, TheSameFramesGiveTheSameBytes) {
  const std::filesystem::path dir = temp_dir("video", "bitexact");
  std::filesystem::create_directories(dir);
  const std::string first = read_text(write_test_video(dir / "a.mp4", 8));
  const std::string second = read_text(write_test_video(dir / "b.mp4", 8));
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(first, second);
}

TEST(VideoWriter, AWriterDroppedBeforeFinishLeavesNoFile) {
  const std::filesystem::path dir = temp_dir("video", "dropped");
  std::filesystem::create_directories(dir);
  {
    VideoWriter writer(dir / "clip.mp4", 64, 48);
    writer.add(test_frame(64, 48, 0));
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(VideoWriter, RefusesBadSizesSettingsAndFrames) {
  const std::filesystem::path dir = temp_dir("video", "errors");
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "clip.mp4").string();
  EXPECT_EQ(error_of([&] { VideoWriter(path, 63, 48); }),
            path + ": expected an even, positive width and height (yuv420p halves them), got 63x48");
  EXPECT_EQ(error_of([&] { VideoWriter(path, 64, 48, {.fps = 0}); }),
            path + ": fps: expected a whole number >= 1, got 0");
  EXPECT_EQ(error_of([&] { VideoWriter(path, 64, 48, {.crf = 60}); }),
            path + ": crf: expected 0..51, got 60");
  EXPECT_EQ(error_of([&] { VideoWriter(path, 64, 48, {.preset = "quick"}); }),
            path + ": preset: expected one of ultrafast, superfast, veryfast, faster, fast, "
                   "medium, slow, slower, veryslow, placebo, got quick");
  VideoWriter writer(path, 64, 48);
  EXPECT_EQ(error_of([&] { writer.add(test_frame(32, 48, 0)); }),
            path + ": frame 0: expected a 64x48 RGB image, got 32x48");
  EXPECT_EQ(error_of([&] { writer.finish(); }), path + ": expected at least one frame, got none");
  EXPECT_EQ(error_of([&] { VideoWriter((dir / "missing" / "clip.mp4").string(), 64, 48); })
                .rfind((dir / "missing" / "clip.mp4").string() + ": cannot write the video: opening ", 0),
            0u);
}

TEST(VideoWriter, NamesItsEncoder) {
  EXPECT_EQ(video_encoder_version().rfind("libavcodec ", 0), 0u);
  EXPECT_NE(video_encoder_version().find("libx264"), std::string::npos);
}

}  // namespace
}  // namespace hribench::io
