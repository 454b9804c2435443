// `hribench merge`: the shards of a sharded eval merged equal the run one process writes, byte
// for byte (options, results, summaries, logs); the shards of a sharded generate merged equal
// the pool one process writes; shards that disagree are refused in one line.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

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

class MergeGenerationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::hribench::testing::temp_dir("merge", "pools");
    ASSERT_EQ(run_hribench(kGenerate + dir_ + "/full").exit_code, 0);
    for (int i = 0; i < 3; ++i) {
      const auto r = run_hribench(kGenerate + dir_ + "/s" + std::to_string(i) + " --shard " + std::to_string(i) + "/3");
      ASSERT_EQ(r.exit_code, 0) << r.output;
      EXPECT_NE(r.output.find("shard " + std::to_string(i) + "/3 of the candidates judged"), std::string::npos) << r.output;
    }
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static inline const std::string kGenerate =
      "generate --tasks I1,I4 --candidates 6 --adapt 2 --eval 1 --test 1 --seed 3 --executable-by none "
      "--threads 2 --quiet --out ";
  static inline std::string dir_;
};

std::vector<std::string> sorted_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::sort(lines.begin(), lines.end());
  return lines;
}

TEST_F(MergeGenerationTest, MergedShardsEqualThePoolOneProcessWrites) {
  const std::string out = dir_ + "/merged";
  const auto r = run_hribench("merge " + out + " " + dir_ + "/s1 " + dir_ + "/s2 " + dir_ + "/s0");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("hribench merge: 3 generation shards -> the pool " + out), std::string::npos) << r.output;
  size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir_ + "/full")) {
    if (!entry.is_regular_file()) continue;
    ++files;
    const fs::path relative = fs::relative(entry.path(), dir_ + "/full");
    const std::string expected = read_text(entry.path());
    const std::string merged = read_text(fs::path(out) / relative);
    if (relative == "candidates.jsonl") {
      // A journal, in the order candidates finished: the same lines.
      EXPECT_EQ(sorted_lines(merged), sorted_lines(expected));
    } else {
      EXPECT_EQ(merged, expected) << relative;
    }
  }
  EXPECT_GT(files, 8u);  // options, candidates, manifest, reports and the episode specs
  EXPECT_TRUE(fs::exists(fs::path(out) / "manifest.json"));
  EXPECT_FALSE(fs::exists(dir_ + "/s0/manifest.json"));  // a shard is no pool
}

TEST_F(MergeGenerationTest, DisagreeingOrIncompleteShardsAreRefused) {
  const auto expect_refused = [](const std::string& args, const std::string& message) {
    const auto r = run_hribench(args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
  };
  expect_refused("merge " + dir_ + "/m1 " + dir_ + "/s0 " + dir_ + "/s2", "merge: shard 1/3 is missing");
  EXPECT_FALSE(fs::exists(dir_ + "/m1"));
  // A shard that did not finish: its last candidate is not in its journal.
  fs::copy(dir_ + "/s1", dir_ + "/s1_unfinished", fs::copy_options::recursive);
  const std::string journal = dir_ + "/s1_unfinished/candidates.jsonl";
  std::string text = read_text(journal);
  text.erase(text.rfind('\n', text.size() - 2) + 1);
  std::ofstream(journal, std::ios::trunc) << text;
  expect_refused("merge " + dir_ + "/m2 " + dir_ + "/s0 " + dir_ + "/s1_unfinished " + dir_ + "/s2",
                 dir_ + "/s1_unfinished: holds 3 of its 4 candidates; finish it with generate --shard 1/3 --resume");
  // Another generation seed.
  std::string seed4 = kGenerate;
  seed4.replace(seed4.find("--seed 3"), 8, "--seed 4");
  ASSERT_EQ(run_hribench(seed4 + dir_ + "/s2_seed4 --shard 2/3").exit_code, 0);
  expect_refused("merge " + dir_ + "/m3 " + dir_ + "/s0 " + dir_ + "/s1 " + dir_ + "/s2_seed4",
                 dir_ + "/s2_seed4: ran with other options than " + dir_ + "/s0 (seed)");
  // The whole pool is not a shard.
  expect_refused("merge " + dir_ + "/m4 " + dir_ + "/full", dir_ + "/full: is not a shard run");
  expect_refused("generate --tasks I1 --shard 1/1 --out " + dir_ + "/bad",
                 "--shard: expected i/N with 0 <= i < N <= 100000 (e.g. 0/4), got '1/1'");
}

}  // namespace
}  // namespace hribench::cli
