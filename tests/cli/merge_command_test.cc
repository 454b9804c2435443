// `hribench merge`: the shards of a sharded eval merged equal the run one process writes, byte
// for byte (options, results, summaries, logs); shards that disagree are refused in one line.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/run_command.h"
#include "support/test_files.h"

namespace hribench::cli {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::count_lines;
using ::hribench::testing::read_text;
using ::hribench::testing::run_hribench;

class MergeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::hribench::testing::temp_dir("merge", "runs");
    const std::string run = "eval --tasks I4,X3 --policy noop,reactive --episodes 2 --horizon 1.5 --threads 2 --save-logs --out ";
    ASSERT_EQ(run_hribench(run + dir_ + "/full").exit_code, 0);
    for (int i = 0; i < 3; ++i) {
      const auto r = run_hribench(run + dir_ + "/s" + std::to_string(i) + " --shard " + std::to_string(i) + "/3");
      ASSERT_EQ(r.exit_code, 0) << r.output;
    }
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static inline std::string dir_;
};

TEST_F(MergeTest, MergedShardsEqualTheFullRun) {
  const std::string out = dir_ + "/merged";
  const auto r = run_hribench("merge " + out + " " + dir_ + "/s2 " + dir_ + "/s0 " + dir_ + "/s1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("hribench merge: 3 shards, 8 episodes -> " + out), std::string::npos) << r.output;
  for (const char* file : {"options.json", "results.json", "summary.md", "summary.csv", "report.html"}) {
    EXPECT_EQ(read_text(fs::path(out) / file), read_text(fs::path(dir_) / "full" / file)) << file;
  }
  EXPECT_EQ(count_lines(read_text(fs::path(out) / "episodes.jsonl")), 8);
  for (const auto& log : fs::directory_iterator(fs::path(dir_) / "full" / "logs")) {
    EXPECT_EQ(read_text(fs::path(out) / "logs" / log.path().filename()), read_text(log.path())) << log.path();
  }
  // A shard holds only its share and records it.
  EXPECT_NE(read_text(fs::path(dir_) / "s1" / "options.json").find("\"shard\": \"1/3\""), std::string::npos);
}

TEST_F(MergeTest, DisagreeingOrIncompleteShardsAreRefused) {
  const auto missing = run_hribench("merge " + dir_ + "/m1 " + dir_ + "/s0 " + dir_ + "/s1");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(count_lines(missing.output), 1) << missing.output;
  EXPECT_NE(missing.output.find("merge: shard 2/3 is missing"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(dir_ + "/m1"));
  const auto not_a_shard = run_hribench("merge " + dir_ + "/m2 " + dir_ + "/full");
  EXPECT_EQ(not_a_shard.exit_code, 2);
  EXPECT_NE(not_a_shard.output.find(dir_ + "/full: is not a shard run"), std::string::npos) << not_a_shard.output;
  const auto into_a_run = run_hribench("merge " + dir_ + "/full " + dir_ + "/s0 " + dir_ + "/s1 " + dir_ + "/s2");
  EXPECT_EQ(into_a_run.exit_code, 2);
  EXPECT_NE(into_a_run.output.find("OUT: expected a new or empty folder for the merged run, got '" + dir_ + "/full'"),
            std::string::npos) << into_a_run.output;
  const auto bad_shard = run_hribench("eval --tasks I4 --policy noop --shard 3/3 --out " + dir_ + "/bad");
  EXPECT_EQ(bad_shard.exit_code, 2);
  EXPECT_NE(bad_shard.output.find("--shard: expected i/N with 0 <= i < N <= 100000 (e.g. 0/4), got '3/3'"),
            std::string::npos) << bad_shard.output;
}

}  // namespace
}  // namespace hribench::cli
