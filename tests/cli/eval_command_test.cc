// Tests of `hribench eval` and `hribench report`: a tiny run (one task, noop, two short
// episodes) writes results.json / summary.md / summary.csv; the folder is refused for a rerun
// without --resume or --force; --resume of a finished run redoes nothing; bad options are one
// line with exit 2; `report` prints a table naming the policy.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "eval/episode_log.h"
#include "support/run_command.h"
#include "support/server_process.h"
#include "support/test_files.h"

namespace hribench::cli {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::count_lines;
using ::hribench::testing::run_hribench;

// A fresh folder per test and process.
std::string temp_dir(const std::string& name) { return ::hribench::testing::temp_dir("eval", name); }
using ::hribench::testing::read_text;

const std::string kTinyRun = "eval --tasks I4 --policy noop --episodes 2 --seed 3 --horizon 2 --out ";

// One tiny run shared by the tests that only read or resume it.
class EvalRunTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = temp_dir("shared");
    first_ = run_hribench(kTinyRun + dir_);
  }
  static inline std::string dir_;
  static inline ::hribench::testing::CommandResult first_;
};

TEST_F(EvalRunTest, WritesResultsAndSummariesWithEveryEpisode) {
  ASSERT_EQ(first_.exit_code, 0) << first_.output;
  const nlohmann::json results = nlohmann::json::parse(read_text(fs::path(dir_) / "results.json"));
  ASSERT_EQ(results.at("episodes").size(), 2u);
  EXPECT_EQ(results.at("episodes")[0].at("seed"), 3);
  EXPECT_EQ(results.at("episodes")[1].at("seed"), 4);
  EXPECT_EQ(results.at("episodes")[0].at("policy"), "noop");
  EXPECT_TRUE(fs::exists(fs::path(dir_) / "summary.csv"));
  EXPECT_TRUE(fs::exists(fs::path(dir_) / "report.html"));
  const std::string summary = read_text(fs::path(dir_) / "summary.md");
  EXPECT_NE(summary.find("noop"), std::string::npos);
  // summary.md is printed without its constants table; the progress line counts to 2 of 2.
  const std::string printed = summary.substr(0, summary.find("\n## Metric constants"));
  EXPECT_NE(first_.output.find(printed), std::string::npos);
  EXPECT_EQ(first_.output.find("| still_sustain |"), std::string::npos) << first_.output;
  EXPECT_NE(summary.find("| still_sustain |"), std::string::npos);
  // The task is shown with its id; episodes carry the id and the variant.
  EXPECT_NE(summary.find("| I4 stop_go | 0.00 | 0 | no_response 2 |"), std::string::npos) << summary;
  EXPECT_EQ(results.at("episodes")[0].at("task_id"), "I4");
  EXPECT_TRUE(results.at("episodes")[0].at("variant").is_string());
  EXPECT_EQ(results.at("aggregates").at("task")[0].at("task_id"), "I4");
  EXPECT_NE(first_.output.find("2/2 episodes"), std::string::npos) << first_.output;
  EXPECT_EQ(count_lines(read_text(fs::path(dir_) / "episodes.jsonl")), 2);
}

TEST_F(EvalRunTest, RerunIntoTheSameFolderIsRefusedInOneLine) {
  ASSERT_EQ(first_.exit_code, 0) << first_.output;
  const auto r = run_hribench(kTinyRun + dir_);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("--resume"), std::string::npos) << r.output;
}

TEST_F(EvalRunTest, ResumeWithOtherOptionsNamesThem) {
  ASSERT_EQ(first_.exit_code, 0) << first_.output;
  const auto r = run_hribench(
      "eval --tasks I4 --policy noop --episodes 3 --seed 4 --horizon 2 --resume --out " + dir_);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("hribench: error: --resume: " + dir_ +
                          " holds a run with other options (episodes: 2 in the run, 3 asked; seed: 3 in "
                          "the run, 4 asked); use --force to replace it"),
            std::string::npos)
      << r.output;
}

// More --episodes with the same options extends a run with the next seeds.
TEST(EvalCommandTest, ResumeWithMoreEpisodesExtendsTheRun) {
  const std::string dir = temp_dir("extend");
  ASSERT_EQ(run_hribench("eval --tasks I4 --policy noop --episodes 1 --seed 3 --horizon 1 --out " + dir).exit_code, 0);
  const auto r = run_hribench("eval --tasks I4 --policy noop --episodes 2 --seed 3 --horizon 1 --resume --out " + dir);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("2/2 episodes (1 resumed)"), std::string::npos) << r.output;
  const nlohmann::json results = nlohmann::json::parse(read_text(fs::path(dir) / "results.json"));
  ASSERT_EQ(results.at("episodes").size(), 2u);
  EXPECT_EQ(results.at("episodes")[1].at("seed"), 4);
  EXPECT_EQ(results.at("options").at("episodes"), 2);
  // Fewer episodes is another run, not a shorter view of this one.
  const auto fewer = run_hribench("eval --tasks I4 --policy noop --episodes 1 --seed 3 --horizon 1 --resume --out " + dir);
  EXPECT_EQ(fewer.exit_code, 2) << fewer.output;
  EXPECT_NE(fewer.output.find("(episodes: 2 in the run, 1 asked)"), std::string::npos) << fewer.output;
}

TEST_F(EvalRunTest, ResumeOfAFinishedRunRedoesNothing) {
  ASSERT_EQ(first_.exit_code, 0) << first_.output;
  const std::string before = read_text(fs::path(dir_) / "results.json");
  const auto r = run_hribench(kTinyRun + dir_ + " --resume");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("episodes ("), std::string::npos) << "no progress line expected";
  EXPECT_NE(r.output.find("hribench eval: nothing to resume: all 2 episodes of " + dir_ + " are finished"),
            std::string::npos) << r.output;
  EXPECT_EQ(count_lines(read_text(fs::path(dir_) / "episodes.jsonl")), 2);
  EXPECT_EQ(read_text(fs::path(dir_) / "results.json"), before);
}

// A run killed after one episode and mid-way through writing the next: --resume redoes only
// the lost episode and ends with the same results.
TEST_F(EvalRunTest, ResumeAfterAKilledRunRedoesOnlyTheLostEpisode) {
  ASSERT_EQ(first_.exit_code, 0) << first_.output;
  const fs::path lines = fs::path(dir_) / "episodes.jsonl";
  const std::string before = read_text(fs::path(dir_) / "results.json");
  const std::string all_lines = read_text(lines);
  std::ofstream(lines) << all_lines.substr(0, all_lines.find('\n') + 1) << "{\"task\": \"st";
  const auto r = run_hribench(kTinyRun + dir_ + " --resume");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("2/2 episodes (1 resumed)"), std::string::npos) << r.output;
  EXPECT_EQ(read_text(lines), all_lines);
  EXPECT_EQ(read_text(fs::path(dir_) / "results.json"), before);
}

TEST_F(EvalRunTest, ReportPrintsATableNamingThePolicy) {
  ASSERT_EQ(first_.exit_code, 0) << first_.output;
  const auto r = run_hribench("report " + dir_);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("|"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("noop"), std::string::npos) << r.output;
}

// --save-logs writes each episode's log next to the results; a reloaded log re-scores to the
// results' metrics (same CT and success) and names its episode.
TEST(EvalCommandTest, SaveLogsWritesOneLogPerEpisode) {
  const std::string dir = temp_dir("logs");
  const auto run = run_hribench("eval --tasks I4 --policy noop,reactive --episodes 1 --seed 3 "
                                "--horizon 2 --threads 2 --save-logs --out " + dir);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::vector<fs::path> logs;
  for (const auto& entry : fs::directory_iterator(fs::path(dir) / "logs")) logs.push_back(entry.path());
  std::sort(logs.begin(), logs.end());
  ASSERT_EQ(logs.size(), 2u);
  const nlohmann::json results = nlohmann::json::parse(read_text(fs::path(dir) / "results.json"));
  for (const nlohmann::json& episode : results.at("episodes")) {
    const std::string stem = "stop_go__" + episode.at("policy").get<std::string>() + "__3__" +
                             episode.at("spec_hash").get<std::string>().substr(0, 12) + ".hlog";
    const fs::path path = fs::path(dir) / "logs" / stem;
    ASSERT_TRUE(fs::exists(path)) << stem;
    const eval::EpisodeLog log = eval::load_episode_log(path);
    EXPECT_EQ(log.policy, episode.at("policy"));
    EXPECT_EQ(log.spec_hash, episode.at("spec_hash"));
    EXPECT_EQ(log.steps.size(), 41u);
    EXPECT_FALSE(log.steps.back().action.empty());
  }
  // --force replaces the logs with the new run's.
  const auto again = run_hribench("eval --tasks I4 --policy noop --episodes 1 --seed 3 --horizon 2 "
                                   "--force --out " + dir);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_FALSE(fs::exists(fs::path(dir) / "logs"));
}

TEST(EvalCommandTest, UnknownTaskIsOneLine) {
  const auto r = run_hribench("eval --tasks Z9_nothing --policy noop --out " + temp_dir("task"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("Z9_nothing"), std::string::npos) << r.output;
}

TEST(EvalCommandTest, UnknownPolicyIsOneLine) {
  const auto r = run_hribench("eval --tasks I4 --policy nosuchpolicy --out " + temp_dir("policy"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("nosuchpolicy"), std::string::npos) << r.output;
}

TEST(EvalCommandTest, ContradictoryOptionsAreOneLine) {
  const std::string dir = temp_dir("options");
  for (const std::string flags : {"--resume --force", "--episodes 0", "--horizon -1.5"}) {
    const auto r = run_hribench("eval --tasks I4 --policy noop " + flags + " --out " + dir);
    EXPECT_EQ(r.exit_code, 2) << flags << ": " << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << flags << ": " << r.output;
  }
  EXPECT_FALSE(fs::exists(dir));
}

TEST(EvalCommandTest, HygieneMessages) {
  const std::string dir = temp_dir("hygiene");
  const auto twice = run_hribench("eval --tasks I4 --policy noop,reactive,noop --out " + dir);
  EXPECT_EQ(twice.exit_code, 2) << twice.output;
  EXPECT_EQ(count_lines(twice.output), 1) << twice.output;
  EXPECT_NE(twice.output.find("--policy: expected each policy once (the same policy twice runs the same "
                              "episodes twice), got 'noop' twice"),
            std::string::npos) << twice.output;
  const auto negative = run_hribench("eval --tasks I4 --policy noop --seed -1 --out " + dir);
  EXPECT_EQ(negative.exit_code, 2) << negative.output;
  EXPECT_EQ(count_lines(negative.output), 1) << negative.output;
  EXPECT_NE(negative.output.find("--seed: expected a non-negative whole number, got '-1'"), std::string::npos)
      << negative.output;
  EXPECT_FALSE(fs::exists(dir));
  // --out a file, or a pool's folder.
  fs::create_directories(dir);
  std::ofstream(fs::path(dir) / "file.txt") << "x";
  const auto file = run_hribench("eval --tasks I4 --policy noop --out " + dir + "/file.txt");
  EXPECT_EQ(file.exit_code, 2) << file.output;
  EXPECT_NE(file.output.find("--out: expected a folder for the run, got '" + dir + "/file.txt', a file"),
            std::string::npos) << file.output;
  fs::create_directories(fs::path(dir) / "pool");
  std::ofstream(fs::path(dir) / "pool" / "manifest.json") << "{}";
  const auto pool = run_hribench("eval --tasks I4 --policy noop --out " + dir + "/pool");
  EXPECT_EQ(pool.exit_code, 2) << pool.output;
  EXPECT_EQ(count_lines(pool.output), 1) << pool.output;
  EXPECT_NE(pool.output.find("which holds an episode pool (manifest.json); choose another folder"),
            std::string::npos) << pool.output;
  EXPECT_FALSE(fs::exists(fs::path(dir) / "pool" / "options.json"));
}

// A --horizon that ends every episode of a task before its first cue is accepted, with a
// warning saying what its scores cannot say.
TEST(EvalCommandTest, HorizonBeforeTheFirstCueIsAWarning) {
  const auto r = run_hribench("eval --tasks I1 --policy noop --episodes 1 --horizon 0.5 --out " + temp_dir("horizon"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("hribench eval: warning: --horizon 0.5 s ends every point_pick episode before its "
                          "first cue; its scores say nothing about responding to the person"),
            std::string::npos) << r.output;
}

TEST(ReportCommandTest, MissingRunIsOneLine) {
  const auto r = run_hribench("report " + temp_dir("missing"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
}

// A remote policy (docs/remote-policies.md) whose server dies mid-run: the episode it dies in
// is a policy_error, the next 3 cannot connect and stop the run with one line (exit 1) without
// being written; --resume with the server back finishes the run.
TEST(EvalCommandTest, RemoteServerGoneStopsTheRunAndResumeContinues) {
  using ::hribench::testing::reference_server;
  using ::hribench::testing::ServerProcess;
  const std::string dir = temp_dir("remote_gone");
  auto server = std::make_unique<ServerProcess>(reference_server("openpi_server.py", {"--mode", "die", "--after", "3"}));
  const std::string port = std::to_string(server->port());
  const std::string run = "eval --tasks I1 --episodes 6 --horizon 1 --policy openpi://127.0.0.1:" + port +
                          "?timeout=2 --out " + dir;
  const auto first = run_hribench(run);
  EXPECT_EQ(first.exit_code, 1) << first.output;
  EXPECT_NE(first.output.find("stopped: 3 episodes in a row could not connect"), std::string::npos) << first.output;
  EXPECT_NE(first.output.find("--resume"), std::string::npos) << first.output;
  std::vector<std::string> statuses;
  std::istringstream lines(read_text(fs::path(dir) / "episodes.jsonl"));
  for (std::string line; std::getline(lines, line);) {
    statuses.push_back(nlohmann::json::parse(line).at("status").get<std::string>());
  }
  EXPECT_EQ(statuses, (std::vector<std::string>{"ok", "policy_error"}));
  EXPECT_FALSE(fs::exists(fs::path(dir) / "results.json"));
  server.reset();
  ServerProcess back(reference_server("openpi_server.py", {"--port", port}));
  const auto resumed = run_hribench(run + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const nlohmann::json results = nlohmann::json::parse(read_text(fs::path(dir) / "results.json"));
  ASSERT_EQ(results.at("episodes").size(), 6u);
  for (size_t i = 2; i < 6; ++i) EXPECT_EQ(results.at("episodes")[i].at("status"), "ok") << i;
}

}  // namespace
}  // namespace hribench::cli
