// Tests of `hribench generate` and `hribench eval --pool`: a tiny pool (one task, four
// candidates, no rollout) is written with its manifest and report and prints the report table;
// rerunning into the same folder is refused; too few candidates names how many are missing;
// `eval --pool DIR --split eval` runs exactly the pool's eval episodes and names the pool
// version in results.json.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "gen/pool.h"
#include "support/run_command.h"
#include "support/test_files.h"

namespace hribench::cli {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::count_lines;
using ::hribench::testing::run_hribench;

// A fresh folder per test and process.
std::string temp_dir(const std::string& name) { return ::hribench::testing::temp_dir("generate", name); }
using ::hribench::testing::read_text;

const std::string kTinyPool =
    "generate --tasks I2 --candidates 4 --adapt 2 --eval 1 --test 0 --seed 5 --executable-by none --quiet --out ";

class GenerateCommandTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = temp_dir("pool");
    first_ = run_hribench(kTinyPool + dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static inline std::string dir_;
  static inline ::hribench::testing::CommandResult first_;
};

TEST_F(GenerateCommandTest, WritesManifestReportAndPrintsTheTable) {
  ASSERT_EQ(first_.exit_code, 0) << first_.output;
  EXPECT_NE(first_.output.find("| gesture_delivery | 4 |"), std::string::npos) << first_.output;
  const nlohmann::json manifest = nlohmann::json::parse(read_text(fs::path(dir_) / "manifest.json"));
  EXPECT_EQ(manifest.at("pool_version"), gen::kPoolVersion);
  EXPECT_EQ(manifest.at("generator").at("executable_by"), "none");
  EXPECT_EQ(manifest.at("generator").at("robot"), "panda");
  EXPECT_GE(manifest.at("episodes").size(), 3u);
  EXPECT_TRUE(fs::exists(fs::path(dir_) / "report.json"));
  EXPECT_TRUE(fs::exists(fs::path(dir_) / "report.md"));
}

TEST_F(GenerateCommandTest, RefusesTheFolderOfAnotherPool) {
  ASSERT_EQ(first_.exit_code, 0) << first_.output;
  const std::string before = read_text(fs::path(dir_) / "manifest.json");
  const auto again = run_hribench(kTinyPool + dir_);
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_EQ(count_lines(again.output), 1) << again.output;
  EXPECT_NE(again.output.find("already holds a pool"), std::string::npos) << again.output;
  EXPECT_EQ(read_text(fs::path(dir_) / "manifest.json"), before);
}

TEST_F(GenerateCommandTest, EvalRunsThePoolSplitAndNamesThePoolVersion) {
  ASSERT_EQ(first_.exit_code, 0) << first_.output;
  const std::string out = temp_dir("eval");
  const auto run = run_hribench("eval --pool " + dir_ + " --split eval --policy noop --horizon 1 --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json manifest = nlohmann::json::parse(read_text(fs::path(dir_) / "manifest.json"));
  const nlohmann::json results = nlohmann::json::parse(read_text(fs::path(out) / "results.json"));
  const nlohmann::json& episodes = results.at("episodes");
  ASSERT_EQ(episodes.size(), 1u);  // one eval episode per task
  bool found = false;
  for (const nlohmann::json& e : manifest.at("episodes")) {
    if (e.at("split") == "eval") {
      EXPECT_EQ(episodes[0].at("seed"), e.at("seed"));
      EXPECT_EQ(episodes[0].at("spec_hash"), e.at("hash"));
      found = true;
    }
  }
  EXPECT_TRUE(found);
  EXPECT_NE(read_text(fs::path(out) / "results.json").find("\"pool_version\": " + std::to_string(gen::kPoolVersion)),
            std::string::npos);
  fs::remove_all(out);
}

TEST_F(GenerateCommandTest, EvalPoolRefusesSamplingFlagsAndUnknownSplits) {
  ASSERT_EQ(first_.exit_code, 0) << first_.output;
  const std::string out = temp_dir("eval_bad");
  auto r = run_hribench("eval --pool " + dir_ + " --episodes 3 --policy noop --out " + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--pool: takes its episodes from the pool; drop --episodes and --seed"),
            std::string::npos) << r.output;
  r = run_hribench("eval --pool " + dir_ + " --split train --policy noop --out " + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--split: expected adapt, eval or test, got 'train'"), std::string::npos) << r.output;
  r = run_hribench("eval --tasks I1 --split adapt --policy noop --out " + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--split: needs --pool (a pool's split)"), std::string::npos) << r.output;
  r = run_hribench("eval --pool " + out + "_none --policy noop --out " + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("holds no pool"), std::string::npos) << r.output;
  fs::remove_all(out);
}

TEST(GenerateCommand, TooFewCandidatesSaysHowManyAreMissing) {
  const std::string dir = temp_dir("few");
  const auto r = run_hribench("generate --tasks I2 --candidates 30 --executable-by none --out " + dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("30 per task cannot fill the splits (50 adapt + 10 eval + 5 test = 65): 35 missing"),
            std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir));
}

TEST(GenerateCommand, AnUnknownRobotIsRefused) {
  const std::string dir = temp_dir("robot");
  const auto r = run_hribench("generate --tasks I1 --robot ur5 --out " + dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("--robot: expected one of panda, got 'ur5'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir));
}

TEST(GenerateCommand, ATaskThatFailsCheckIsRefused) {
  const std::string dir = temp_dir("badtask");
  const auto r = run_hribench("generate --tasks tests/data/scripts/bad/bad_normal.yaml --candidates 70 --out " + dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("tests/data/scripts/bad/bad_normal.yaml:"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir));
}

}  // namespace
}  // namespace hribench::cli
