// Tests of `hribench collect` and `hribench replay`: bad options are one line and exit 2 (an
// unknown format, split, policy or camera; a folder holding something else; a dataset folder
// reused without --resume or --force); a one-episode collect replays identically through the
// command; --help lists the formats.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/run_command.h"
#include "support/test_files.h"

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
  expect_refused(base + " --cameras wrist --format parquet", "--format: expected one of act-hdf5, robomimic, got 'parquet'");
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
  EXPECT_NE(r.output.find("act-hdf5, robomimic"), std::string::npos) << r.output;
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

TEST(ReplayCommand, RefusesAFolderThatIsNotACollect) {
  const std::string dir = temp_dir("not_collect");
  fs::create_directories(dir);
  expect_refused("replay --dataset " + dir,
                 "--dataset: expected a folder written by hribench collect (hribench/collect.json), got '" + dir + "'");
}

}  // namespace
}  // namespace hribench::cli
