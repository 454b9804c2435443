// hribench eval --video and hribench video (docs/videos.md).

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/run_command.h"
#include "support/test_files.h"
#include "support/video_probe.h"

namespace hribench::testing {
namespace {

namespace fs = std::filesystem;

// A 1.5 s run of I1 (the noop fails it, the oracle cannot finish it): videos of the failures.
class VideoRunTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::string(temp_dir("video_command", "run"));
    const auto r = run_hribench("eval --tasks I1 --policy noop --episodes 2 --horizon 1.5 --save-logs "
                                "--video failures --video-cameras agentview,wrist --out " + *dir_);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string* dir_;
};
std::string* VideoRunTest::dir_ = nullptr;

TEST_F(VideoRunTest, EvalWritesAVideoPerFailedEpisode) {
  std::ifstream in(fs::path(*dir_) / "results.json");
  const auto results = nlohmann::json::parse(in);
  size_t failed = 0;
  for (const auto& episode : results.at("episodes")) failed += episode.at("success").get<bool>() ? 0 : 1;
  ASSERT_EQ(failed, 2u);
  size_t videos = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(*dir_) / "videos")) {
    ++videos;
    EXPECT_TRUE(fs::exists(fs::path(*dir_) / "logs" / (entry.path().stem().string() + ".hlog")))
        << "a video shares its episode's log stem: " << entry.path();
    const VideoProbe video = probe_video(entry.path().string());
    EXPECT_EQ(video.codec, "h264");
    EXPECT_EQ(video.width, 640);  // two 320-pixel cameras side by side
    EXPECT_EQ(video.height, 280);  // 240 pixels of picture and a 40-pixel band
    EXPECT_EQ(video.frames, 31);   // steps 0..30 of 1.5 s at 20 Hz
  }
  EXPECT_EQ(videos, failed);
}

TEST_F(VideoRunTest, TheVideoOfASavedLogIsTheVideoEvalWrote) {
  const fs::path first = fs::directory_iterator(fs::path(*dir_) / "videos")->path();
  const std::string again = (fs::path(temp_dir("video_command", "again")) / "again.mp4").string();
  const auto r = run_hribench("video " + *dir_ + " " + first.stem().string() +
                              " --cameras agentview,wrist --out " + again);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("wrote " + again + " (31 frames)"), std::string::npos) << r.output;
  EXPECT_EQ(read_text(again), read_text(first));
}

// --failures 1 on a copy of the run without its videos: the video of the first failed episode
// in results.json's order (both fail, one task, one policy); --failures and EPISODE exclude each
// other.
TEST_F(VideoRunTest, FailuresMakesTheVideosOfTheFirstFailuresOfEachTaskAndPolicy) {
  const fs::path copy = fs::path(temp_dir("video_command", "failures")) / "run";
  fs::create_directories(copy);
  fs::copy(*dir_, copy, fs::copy_options::recursive);
  fs::remove_all(copy / "videos");
  auto r = run_hribench("video " + copy.string() + " --failures 1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(copy / "results.json");
  const auto first = nlohmann::json::parse(in).at("episodes").at(0);
  const std::string stem = "point_pick__noop__" + std::to_string(first.at("seed").get<uint64_t>()) + "__" +
                           first.at("spec_hash").get<std::string>().substr(0, 12);
  EXPECT_EQ(std::distance(fs::directory_iterator(copy / "videos"), fs::directory_iterator()), 1);
  ASSERT_TRUE(fs::exists(copy / "videos" / (stem + ".mp4"))) << r.output;
  const VideoProbe video = probe_video((copy / "videos" / (stem + ".mp4")).string());
  EXPECT_EQ(video.width, 320) << "agentview alone by default";
  EXPECT_EQ(video.frames, 31);
  r = run_hribench("video " + copy.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("EPISODE: expected a log stem of " + copy.string() + "/logs, or --failures N, got neither"),
            std::string::npos)
      << r.output;
  r = run_hribench("video " + copy.string() + " " + stem + " --failures 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--failures: expected either EPISODE or --failures N, got both (EPISODE '" + stem + "')"),
            std::string::npos)
      << r.output;
  r = run_hribench("video " + copy.string() + " --failures 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--failures: expected a positive number, got 0"), std::string::npos) << r.output;
  r = run_hribench("video " + copy.string() + " --failures 1 --out x.mp4");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--out: expected one EPISODE (--out names one file), got --failures, which makes several"),
            std::string::npos)
      << r.output;
}

TEST_F(VideoRunTest, BadRequestsAreOneLine) {
  auto r = run_hribench("video " + *dir_ + " nope");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("EPISODE: expected an episode of " + *dir_ + " (a log stem, e.g. point_pick__noop__"),
            std::string::npos)
      << r.output;
  r = run_hribench("video " + *dir_ + " " + fs::directory_iterator(fs::path(*dir_) / "videos")->path().stem().string() +
                   " --size 321x240");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--size: expected WIDTHxHEIGHT of each camera, even numbers of pixels (e.g. 320x240), got "
                          "'321x240'"),
            std::string::npos)
      << r.output;
  const std::string other = temp_dir("video_command", "bad_flags");
  r = run_hribench("eval --tasks I1 --policy noop --episodes 1 --horizon 1 --video some --out " + other);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--video: expected none, failures or all, got 'some'"), std::string::npos) << r.output;
  r = run_hribench("eval --tasks I1 --policy noop --episodes 1 --horizon 1 --video all --video-cameras top --out " +
                   other);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--video-cameras: expected one of"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(fs::path(other) / "episodes.jsonl")) << "refused before any episode ran";
}

}  // namespace
}  // namespace hribench::testing
