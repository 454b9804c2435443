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
  fs::create_directories(out);  // an empty OUT is taken
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
  EXPECT_FALSE(fs::exists(dir_ + "/.merged.merging"));  // the staging folder became OUT
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

// Sharded collects: every format, 4 episodes over 3 shards (2, 1 and 1), frames of 64 px (x264
// encodes smaller ones differently from one process to the next: docs/datasets.md).
class MergeCollectTest : public ::testing::TestWithParam<std::string> {
 protected:
  static void SetUpTestSuite() { dir_ = ::hribench::testing::temp_dir("merge", "collects"); }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string collect(const std::string& format) {
    return "collect --tasks C2,X3 --episodes 2 --size 64 --cameras wrist --keep all --threads 2 --format " + format +
           " --out ";
  }
  static inline std::string dir_;
};

TEST_P(MergeCollectTest, MergedShardsEqualTheDatasetOneCollectWrites) {
  const std::string format = GetParam();
  const fs::path root = fs::path(dir_) / format;
  ASSERT_EQ(run_hribench(collect(format) + (root / "full").string()).exit_code, 0);
  for (int i = 0; i < 3; ++i) {
    const auto r = run_hribench(collect(format) + (root / ("s" + std::to_string(i))).string() + " --shard " +
                                std::to_string(i) + "/3");
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  const fs::path out = root / "merged";
  const auto r = run_hribench("merge " + out.string() + " " + (root / "s2").string() + " " + (root / "s0").string() +
                              " " + (root / "s1").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("4 episodes, 4 in the dataset at " + out.string()), std::string::npos) << r.output;
  // The dataset's files, collect.json and four logs.
  EXPECT_GE(::hribench::testing::expect_same_files(out, root / "full"), 6u);
  // A shard writes no dataset files: its kept episodes wait in hribench/episodes/ for the merge.
  EXPECT_TRUE(fs::is_directory(root / "s1" / "hribench" / "episodes"));
  for (const auto& entry : fs::directory_iterator(root / "s1")) EXPECT_EQ(entry.path().filename(), "hribench");
  EXPECT_NE(read_text(root / "s1" / "hribench" / "collect.json").find("\"shard\": \"1/3\""), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Formats, MergeCollectTest, ::testing::Values("lerobot", "lerobot-v3", "act-hdf5", "robomimic"),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                           std::string name = param.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST(MergeCollect, DisagreeingOrIncompleteShardsAreRefused) {
  const fs::path root = ::hribench::testing::temp_dir("merge", "collect_refusals");
  const std::string collect = "collect --tasks C2 --episodes 2 --size 32 --cameras wrist --format act-hdf5 --out ";
  for (int i = 0; i < 2; ++i) {
    const std::string shard = std::to_string(i) + "/2";
    ASSERT_EQ(run_hribench(collect + (root / ("s" + std::to_string(i))).string() + " --shard " + shard).exit_code, 0);
  }
  const auto expect_refused = [&](const std::string& args, const std::string& message, const std::string& out) {
    const auto r = run_hribench("merge " + (root / out).string() + " " + args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(root / out)) << out;
  };
  const std::string s0 = (root / "s0").string(), s1 = (root / "s1").string();
  expect_refused(s0, "merge: shard 1/2 is missing", "m1");
  // Another format.
  std::string robomimic = collect;
  robomimic.replace(robomimic.find("act-hdf5"), 8, "robomimic");
  ASSERT_EQ(run_hribench(robomimic + (root / "s1_robomimic").string() + " --shard 1/2").exit_code, 0);
  expect_refused(s0 + " " + (root / "s1_robomimic").string(),
                 (root / "s1_robomimic").string() + ": ran with other options than " + s0 + " (format)", "m2");
  // A shard that did not finish, and one that lost an episode.
  fs::copy(s1, root / "s1_unfinished", fs::copy_options::recursive);
  const fs::path state = root / "s1_unfinished" / "hribench" / "collect.json";
  std::string text = read_text(state);
  text.replace(text.find("\"finished\": true"), 16, "\"finished\": false");
  std::ofstream(state, std::ios::trunc) << text;
  expect_refused(s0 + " " + (root / "s1_unfinished").string(),
                 (root / "s1_unfinished").string() + ": holds an unfinished collect; finish it with collect --shard 1/2 "
                                                     "--resume",
                 "m3");
  // A state that is no collect's.
  fs::copy(s1, root / "s1_bad", fs::copy_options::recursive);
  std::ofstream(root / "s1_bad" / "hribench" / "collect.json", std::ios::trunc) << R"({"options": {}, "episodes": [3]})";
  expect_refused(s0 + " " + (root / "s1_bad").string(),
                 (root / "s1_bad" / "hribench" / "collect.json").string() +
                     ": expected a collect's state (options, episodes, finished), got other JSON",
                 "m6");
  // A stored episode that cannot be read fails the merge after its checks: OUT is not left half
  // written, and the staging folder is gone.
  fs::copy(s1, root / "s1_torn", fs::copy_options::recursive);
  for (const auto& stored : fs::recursive_directory_iterator(root / "s1_torn" / "hribench" / "episodes")) {
    if (stored.is_regular_file()) std::ofstream(stored.path(), std::ios::trunc) << "not an episode";
  }
  expect_refused(s0 + " " + (root / "s1_torn").string(), (root / "s1_torn" / "hribench" / "episodes").string(), "m7");
  EXPECT_FALSE(fs::exists(root / ".m7.merging"));
  // The whole collect is not a shard; an eval shard is no collect.
  ASSERT_EQ(run_hribench(collect + (root / "whole").string()).exit_code, 0);
  expect_refused((root / "whole").string(), (root / "whole").string() + ": is not a shard run", "m4");
  ASSERT_EQ(run_hribench("eval --tasks C2 --policy noop --episodes 1 --horizon 1 --shard 1/2 --out " +
                         (root / "eval_s1").string()).exit_code, 0);
  expect_refused(s0 + " " + (root / "eval_s1").string(),
                 (root / "eval_s1").string() + ": holds no collect (hribench/collect.json)", "m5");
  const auto into_a_shard = run_hribench("merge " + s0 + " " + s0 + " " + s1);
  EXPECT_EQ(into_a_shard.exit_code, 2);
  EXPECT_NE(into_a_shard.output.find("OUT: expected a new or empty folder for the merged dataset, got '" + s0 + "'"),
            std::string::npos)
      << into_a_shard.output;
  fs::remove_all(root);
}

}  // namespace
}  // namespace hribench::cli
