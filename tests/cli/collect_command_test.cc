// Tests of `hribench collect` and `hribench replay`: bad options are one line and exit 2 (an
// unknown format, split, policy or camera; a folder holding something else; a dataset folder
// reused without --resume or --force); a one-episode collect replays identically through the
// command, in an HDF5 and in both LeRobot formats; --help lists the formats.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/parquet_readers.h"
#include "support/run_command.h"
#include "support/test_files.h"
#include "support/video_probe.h"

namespace hribench::cli {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::count_lines;
using ::hribench::testing::run_hribench;

std::string temp_dir(const std::string& name) { return ::hribench::testing::temp_dir("collect_cli", name); }

const std::string kSmall = "collect --tasks C2 --episodes 1 --size 16 --cameras wrist --format act-hdf5 --out ";

// Exit 2 and one line holding `message`.
void expect_refused(const std::string& args, const std::string& message) {
  const auto r = run_hribench(args);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
}

TEST(CollectCommand, RefusesBadOptionsInOneLine) {
  const std::string dir = temp_dir("bad");
  const std::string base = "collect --tasks C2 --episodes 1 --size 16 --out " + dir;
  expect_refused(base + " --cameras wrist --format parquet", "--format: expected one of lerobot, lerobot-v3, act-hdf5, robomimic, got 'parquet'");
  expect_refused(kSmall + dir + " --split train", "--split: expected adapt, eval or test, got 'train'");
  expect_refused(kSmall + dir + " --policy nobody", "'nobody'");
  expect_refused(base + " --format robomimic --cameras top", "--cameras: expected one of ");
  expect_refused(kSmall + dir + " --episodes -1", "--episodes");
  EXPECT_FALSE(fs::exists(dir));
  fs::create_directories(dir);
  std::ofstream(dir + "/results.json") << "{}\n";
  expect_refused(kSmall + dir, "holds files that are not a hribench collect");
}

TEST(CollectCommand, HelpListsTheFormats) {
  const auto r = run_hribench("collect --help");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("lerobot, lerobot-v3, act-hdf5, robomimic"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--dry-run"), std::string::npos) << r.output;
}

TEST(CollectCommand, ACollectReplaysIdenticallyAndIsNotOverwritten) {
  const std::string dir = temp_dir("one");
  const auto first = run_hribench(kSmall + dir);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_NE(first.output.find("1/1 episodes (0 resumed), 1 kept"), std::string::npos) << first.output;
  EXPECT_TRUE(fs::exists(fs::path(dir) / "handover_r2h" / "episode_0.hdf5"));
  const auto replay = run_hribench("replay --dataset " + dir);
  EXPECT_EQ(replay.exit_code, 0) << replay.output;
  EXPECT_NE(replay.output.find("1 episodes replayed, 1 identical to the collect's logs"), std::string::npos)
      << replay.output;
  expect_refused(kSmall + dir, dir + " already holds a dataset; use --resume to continue it or --force to replace it");
  const auto resumed = run_hribench(kSmall + dir + " --resume");
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("nothing to resume"), std::string::npos) << resumed.output;
}

// A LeRobot dataset (v2.1 and v3.0) of a real rollout, both cameras, replays identically: its
// parquet actions are the executed ones, read back by the dataset reader of io/lerobot.h.
TEST(CollectCommand, ALeRobotCollectReplaysIdentically) {
  for (const std::string format : {"lerobot", "lerobot-v3"}) {
    const std::string dir = temp_dir(format);
    const auto collect = run_hribench("collect --tasks C2 --episodes 1 --size 16 --cameras agentview,wrist --format " +
                                      format + " --out " + dir);
    ASSERT_EQ(collect.exit_code, 0) << format << ": " << collect.output;
    EXPECT_TRUE(fs::exists(fs::path(dir) / "meta" / "info.json")) << format;
    // Both real readers read every parquet file; every mp4 has one frame per data row.
    std::vector<std::string> parquet;
    int64_t rows = 0;
    std::vector<std::string> videos;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
      if (entry.path().extension() == ".parquet") parquet.push_back(entry.path().string());
      if (entry.path().extension() == ".mp4") videos.push_back(entry.path().string());
    }
    const nlohmann::json read = ::hribench::testing::read_with_real_readers(parquet);
    ASSERT_FALSE(read.is_null()) << format;
    for (const auto& [file, readers] : read.items()) {
      EXPECT_EQ(readers.at("hyparquet").at("num_rows"), readers.at("duckdb").at("rows").size()) << file;
      if (file.find("/data/") != std::string::npos) rows += readers.at("hyparquet").at("num_rows").get<int64_t>();
    }
    ASSERT_EQ(videos.size(), 2u) << format << ": one video per camera";
    for (const std::string& video : videos) {
      EXPECT_EQ(::hribench::testing::probe_video(video).frames, rows) << video;
    }
    const auto replay = run_hribench("replay --dataset " + dir);
    EXPECT_EQ(replay.exit_code, 0) << format << ": " << replay.output;
    EXPECT_NE(replay.output.find("1 episodes replayed, 1 identical to the collect's logs"), std::string::npos)
        << format << ": " << replay.output;
  }
}

TEST(ReplayCommand, RefusesAFolderThatIsNotACollect) {
  const std::string dir = temp_dir("not_collect");
  fs::create_directories(dir);
  expect_refused("replay --dataset " + dir,
                 "--dataset: expected a folder written by hribench collect (hribench/collect.json), got '" + dir + "'");
}

}  // namespace
}  // namespace hribench::cli
