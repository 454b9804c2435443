#include "gen/generate.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "core/errors.h"
#include "core/json.h"
#include "script/check.h"
#include "script/sample.h"
#include "support/test_files.h"

namespace hribench::gen {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using ::hribench::testing::error_of;
std::string read_file(const fs::path& path) { return ::hribench::testing::read_text(path); }

class GenerateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hrib_gen_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A task that validates nearly every candidate, small splits, no rollout.
  GenerateOptions options(const std::string& out, int threads = 1) const {
    GenerateOptions o;
    o.scripts = {"tasks/I2_gesture_delivery.yaml"};
    o.candidates = 4;
    o.seed = 11;
    o.threads = threads;
    o.splits = SplitSizes{2, 1, 0};
    o.filters.executable_by = "none";
    o.out = (dir_ / out).string();
    o.progress = false;
    return o;
  }
  fs::path dir_;
};

TEST_F(GenerateTest, WritesAPoolThatIsTheSameForAnyThreadCount) {
  GenerateOptions o = options("one", 1);
  o.scripts.push_back("tasks/I4_stop_go.yaml");
  o.candidates = 5;
  const GenerationReport one = generate(o);
  o.threads = 2;
  o.out = (dir_ / "two").string();
  generate(o);
  for (const char* file : {"manifest.json", "report.json", "report.md"}) {
    EXPECT_EQ(read_file(dir_ / "one" / file), read_file(dir_ / "two" / file)) << file;
  }
  const Manifest manifest = read_manifest((dir_ / "one").string());
  ASSERT_EQ(one.tasks.size(), 2u);
  EXPECT_EQ(one.total.candidates, 10u);
  EXPECT_EQ(one.tasks[1].task, "stop_go");
  EXPECT_EQ(manifest.episodes.size(), one.total.validated);
  std::map<std::string, std::map<Split, int>> counts;
  for (const PoolEntry& e : manifest.episodes) {
    ++counts[e.task][e.split];
    EXPECT_EQ(e.seed, candidate_seed(11, e.task, e.candidate));
    // Each episode's spec file is written and reloads to the same hash.
    const fs::path spec_file = dir_ / "one" / "episodes" / e.task / ("c000" + std::to_string(e.candidate) + ".json");
    ASSERT_TRUE(fs::exists(spec_file)) << spec_file;
    EXPECT_EQ(script::spec_hash(script::spec_from_text(read_file(spec_file), spec_file.string())), e.hash);
  }
  for (const TaskReport& t : one.tasks) {
    EXPECT_EQ(counts[t.task][Split::kAdapt], 2);
    EXPECT_EQ(counts[t.task][Split::kEval], 1);
    EXPECT_EQ(counts[t.task][Split::kTest], static_cast<int>(t.validated) - 3);
    // Filter pass counts never grow along the pipeline.
    for (size_t k = 1; k < kNumFilters; ++k) EXPECT_LE(t.passed[k], t.passed[k - 1]);
    EXPECT_EQ(t.passed[kNumFilters - 1], t.validated);
  }
  EXPECT_THAT(report_markdown(one), HasSubstr("| task | candidates | ordering | scene |"));
}

TEST_F(GenerateTest, ResumesAnInterruptedGenerationToTheSamePool) {
  generate(options("full"));
  // An interrupted run: its options, two judged candidates and a torn third line.
  const GenerateOptions o = options("cut");
  fs::create_directories(o.out);
  fs::copy_file(dir_ / "full" / "options.json", fs::path(o.out) / "options.json");
  std::istringstream lines(read_file(dir_ / "full" / "candidates.jsonl"));
  std::ofstream cut(fs::path(o.out) / "candidates.jsonl", std::ios::binary);
  std::string line;
  for (int i = 0; i < 2 && std::getline(lines, line); ++i) cut << line << "\n";
  std::getline(lines, line);
  cut << line.substr(0, line.size() / 2);
  cut.close();
  EXPECT_THAT(error_of([&] { generate(o); }), HasSubstr("holds an unfinished generation; use --resume"));
  GenerateOptions resumed = o;
  resumed.resume = true;
  generate(resumed);
  EXPECT_EQ(read_file(dir_ / "full" / "manifest.json"), read_file(dir_ / "cut" / "manifest.json"));
}

TEST_F(GenerateTest, AResumeAfterTheScriptsChangedIsRefused) {
  generate(options("judged"));
  // The same judged candidates, as if their script had sampled other episodes back then.
  const GenerateOptions o = options("changed");
  fs::create_directories(o.out);
  fs::copy_file(dir_ / "judged" / "options.json", fs::path(o.out) / "options.json");
  std::string lines = read_file(dir_ / "judged" / "candidates.jsonl");
  for (size_t at = lines.find("\"hash\":\""); at != std::string::npos; at = lines.find("\"hash\":\"", at + 1)) {
    lines.replace(at + 8, 64, std::string(64, '0'));
  }
  std::ofstream(fs::path(o.out) / "candidates.jsonl", std::ios::binary) << lines;
  GenerateOptions resumed = o;
  resumed.resume = true;
  EXPECT_THAT(error_of([&] { generate(resumed); }),
              HasSubstr("the script changed since the generation began: generate again without --resume"));
  EXPECT_FALSE(fs::exists(fs::path(o.out) / "manifest.json"));
}

TEST_F(GenerateTest, RefusesAFolderHoldingAnotherPoolWithoutTouchingIt) {
  const GenerateOptions o = options("pool");
  generate(o);
  const std::string manifest = read_file(fs::path(o.out) / "manifest.json");
  GenerateOptions other = o;
  other.seed = 12;
  EXPECT_EQ(error_of([&] { generate(other); }),
            o.out + ": already holds a pool (manifest.json); choose another --out");
  other.resume = true;
  EXPECT_THAT(error_of([&] { generate(other); }), HasSubstr("already holds a pool"));
  EXPECT_EQ(read_file(fs::path(o.out) / "manifest.json"), manifest);
  // Its own generation resumed (killed after the manifest was written) redoes nothing.
  GenerateOptions same = o;
  same.resume = true;
  generate(same);
  EXPECT_EQ(read_file(fs::path(o.out) / "manifest.json"), manifest);
}

TEST_F(GenerateTest, TooFewCandidatesSaysHowManyAreMissing) {
  GenerateOptions o = options("few");
  o.candidates = 2;
  EXPECT_EQ(error_of([&] { generate(o); }),
            "--candidates: 2 per task cannot fill the splits (2 adapt + 1 eval + 0 test = 3): 1 missing");
  EXPECT_FALSE(fs::exists(o.out));
  // Enough candidates, but not enough of them validate.
  o.candidates = 3;
  o.splits = SplitSizes{2, 1, 0};
  o.scripts = {"tasks/X4_blocked_target.yaml"};
  o.out = (dir_ / "few2").string();
  const std::string e = error_of([&] { generate(o); });
  if (e != "(no error)") {  // all three may validate; then there is nothing to check
    EXPECT_THAT(e, HasSubstr("too few validated episodes to fill the splits: blocked_target has"));
    EXPECT_THAT(e, HasSubstr("missing"));
    EXPECT_FALSE(fs::exists(fs::path(o.out) / "manifest.json"));
  }
}

TEST_F(GenerateTest, BadScriptsAndPoliciesAreRefusedBeforeWriting) {
  GenerateOptions o = options("bad");
  fs::create_directories(dir_);
  const fs::path broken = dir_ / "broken.yaml";
  std::ofstream(broken) << "hribench: 1\ntask: x\n";
  o.scripts = {broken.string()};
  EXPECT_THAT(error_of([&] { generate(o); }), HasSubstr("broken.yaml"));
  o = options("bad");
  o.filters.executable_by = "no_such_policy";
  EXPECT_THAT(error_of([&] { generate(o); }), HasSubstr("no_such_policy"));
  o = options("bad");
  o.threads = 0;
  EXPECT_EQ(error_of([&] { generate(o); }), "--threads: expected a positive number, got 0");
  o = options("bad");
  o.scripts = {"tasks/I4_stop_go.yaml", "tasks/I4_stop_go.yaml"};
  EXPECT_EQ(error_of([&] { generate(o); }), "--tasks: task 'stop_go' is given twice");
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

TEST(CandidateRecord, RoundTripsThroughJson) {
  CandidateRecord r{"stop_go", 7, 99, "abc", Filter::kVisibility, "hidden"};
  const CandidateRecord back = candidate_from_json(to_json(r), "line");
  EXPECT_EQ(back.task, r.task);
  EXPECT_EQ(back.index, 7u);
  EXPECT_EQ(back.seed, 99u);
  EXPECT_EQ(back.failed, Filter::kVisibility);
  EXPECT_EQ(back.reason, "hidden");
  core::Json bad = to_json(r);
  bad["failed"] = "bogus";
  EXPECT_EQ(error_of([&] { candidate_from_json(bad, "line"); }),
            "line (failed): expected a filter name, got \"bogus\"");
}

// The committed pools (pool/*/manifest.json): a sample of each (the first eval episode of
// every task) is judged again with the manifest's generator options and must give the same
// seeds, hashes and verdicts. docs/generation.md gives the command that regenerates a pool in
// full.
TEST(ReleasedPool, ASampleOfEveryCommittedPoolIsReproduced) {
  size_t pools = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator("pool")) {
    if (!fs::exists(entry.path() / "manifest.json")) continue;
    ++pools;
    const Manifest manifest = read_manifest(entry.path().string());
    const core::Json& g = manifest.generator;
    const uint64_t seed = g.at("seed").get<uint64_t>();
    FilterOptions filters;
    filters.executable_by = g.at("executable_by").get<std::string>();
    std::map<std::string, bool> sampled;
    for (const PoolEntry& e : manifest.episodes) {
      if (e.split != Split::kEval || sampled[e.task]) continue;
      sampled[e.task] = true;
      const CandidateRecord r = judge_candidate(script::load_scenario(e.script), e.task, e.candidate, seed, pool_robot(manifest), filters);
      const std::string what = entry.path().string() + ": " + e.task + " candidate " + std::to_string(e.candidate);
      EXPECT_EQ(r.seed, e.seed) << what;
      EXPECT_EQ(r.hash, e.hash) << what << ": the pool changed; regenerate it and bump kPoolVersion";
      EXPECT_FALSE(r.failed) << what << " now fails " << (r.failed ? to_string(*r.failed) : "") << ": " << r.reason;
    }
    EXPECT_EQ(sampled.size(), g.at("tasks").size()) << entry.path();
  }
  EXPECT_GT(pools, 0u) << "no committed pool under pool/";
}

// The released pool: pool/vN with the largest N.
fs::path newest_released_pool() {
  fs::path newest;
  int version = -1;
  for (const fs::directory_entry& entry : fs::directory_iterator("pool")) {
    const std::string name = entry.path().filename().string();
    if (name.size() < 2 || name[0] != 'v' || name.find_first_not_of("0123456789", 1) != std::string::npos) continue;
    if (std::stoi(name.substr(1)) > version && fs::exists(entry.path() / "manifest.json")) {
      version = std::stoi(name.substr(1));
      newest = entry.path();
    }
  }
  return newest;
}

// Issue 16: the person never touches a robot at rest. The generator's at_rest filter passed
// every released episode; here it is re-run on every eval episode of the released pool (a
// full-horizon noop rollout each, 130 in all, on every core: about 3 min on 2 cores).
TEST(ReleasedPool, ThePersonNeverTouchesTheRobotAtRestInTheEvalSplit) {
  const fs::path pool = newest_released_pool();
  ASSERT_FALSE(pool.empty()) << "no released pool pool/vN";
  // pool_episodes re-samples each for the pool's robot and checks it against the manifest hash.
  const std::vector<script::EpisodeSpec> specs = pool_episodes(read_manifest(pool.string()), Split::kEval);
  ASSERT_EQ(specs.size(), 130u) << pool << ": expected 10 eval episodes of each of the 13 tasks";
  std::vector<FilterOutcome> outcomes(specs.size());
  std::atomic<size_t> next{0};
  std::vector<std::thread> workers;
  for (unsigned t = 0; t < std::max(1u, std::thread::hardware_concurrency()); ++t) {
    workers.emplace_back([&] {
      for (size_t i = next++; i < specs.size(); i = next++) {
        try {
          outcomes[i] = check_at_rest(specs[i]);
        } catch (const std::exception& e) {
          outcomes[i] = FilterOutcome::Fail(e.what());
        }
      }
    });
  }
  for (std::thread& w : workers) w.join();
  for (size_t i = 0; i < specs.size(); ++i) {
    EXPECT_TRUE(outcomes[i].ok) << pool.string() << ": " << specs[i].task << " seed " << specs[i].seed << ": "
                                << outcomes[i].reason;
  }
}

}  // namespace
}  // namespace hribench::gen
