// Tests of `hribench serve`: the oracle served over openpi and evaluated through our openpi
// client gives the in-process oracle's episodes exactly (results and logs) under --latency none;
// bad options are one line.

#include <gtest/gtest.h>

#include <filesystem>
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
using ::hribench::testing::read_text;
using ::hribench::testing::run_hribench;
using ::hribench::testing::ServerProcess;

std::string temp_dir(const std::string& name) { return ::hribench::testing::temp_dir("serve", name); }

std::vector<nlohmann::json> episodes(const std::string& dir) {
  std::vector<nlohmann::json> out;
  std::istringstream lines(read_text(fs::path(dir) / "episodes.jsonl"));
  for (std::string line; std::getline(lines, line);) out.push_back(nlohmann::json::parse(line));
  // In seed order (the file is in completion order: two threads).
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.at("seed") < b.at("seed"); });
  return out;
}

std::vector<fs::path> logs(const std::string& dir) {
  std::vector<fs::path> out;
  for (const auto& entry : fs::directory_iterator(fs::path(dir) / "logs")) out.push_back(entry.path());
  std::sort(out.begin(), out.end());
  return out;
}

// Evaluates `policy` on two short episodes of I1 (the server's reference and the in-process
// oracle get the same episodes), on two threads: a server serves two clients at once, each
// its own episode.
::hribench::testing::CommandResult eval_into(const std::string& dir, const std::string& policy) {
  return run_hribench("eval --tasks I1 --episodes 2 --seed 5 --horizon 3 --latency none --threads 2 --save-logs "
                      "--policy '" + policy + "' --out " + dir);
}

void expect_same_episodes(const std::string& local, const std::string& remote) {
  const std::vector<nlohmann::json> a = episodes(local);
  const std::vector<nlohmann::json> b = episodes(remote);
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), 2u);
  for (size_t i = 0; i < a.size(); ++i) {
    nlohmann::json x = a[i];
    nlohmann::json y = b[i];
    EXPECT_EQ(y.at("status"), "ok") << y.dump();
    x.erase("policy");
    y.erase("policy");
    EXPECT_EQ(x, y) << "episode " << i;
  }
  const std::vector<fs::path> la = logs(local);
  const std::vector<fs::path> lb = logs(remote);
  ASSERT_EQ(la.size(), 2u);
  ASSERT_EQ(lb.size(), 2u);
  for (size_t i = 0; i < la.size(); ++i) {
    eval::EpisodeLog x = eval::load_episode_log(la[i]);
    eval::EpisodeLog y = eval::load_episode_log(lb[i]);
    ASSERT_GT(x.steps.size(), 10u);
    EXPECT_FALSE(x.steps.back().action.empty());
    y.policy = x.policy;
    EXPECT_TRUE(eval::identical(x, y)) << la[i] << " vs " << lb[i];
  }
}

TEST(ServeCommandTest, OracleOverOpenpiReproducesTheInProcessOracle) {
  ServerProcess server({HRIBENCH_BINARY, "serve", "--policy", "oracle", "--protocol", "openpi", "--port", "0"});
  EXPECT_NE(server.first_line().find("oracle over openpi at ws://127.0.0.1:"), std::string::npos) << server.first_line();
  const std::string local = temp_dir("oracle_local");
  const std::string remote = temp_dir("oracle_openpi");
  ASSERT_EQ(eval_into(local, "oracle").exit_code, 0);
  const auto r = eval_into(remote, "openpi://127.0.0.1:" + std::to_string(server.port()) + "?privileged=1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_same_episodes(local, remote);
}

TEST(ServeCommandTest, OracleOverGr00tReproducesTheInProcessOracleInBothEras) {
  const std::string local = temp_dir("oracle_local_g");
  ASSERT_EQ(eval_into(local, "oracle").exit_code, 0);
  for (const std::string era : {"n15", "n16"}) {
    ServerProcess server({HRIBENCH_BINARY, "serve", "--policy", "oracle", "--protocol", "gr00t", "--port", "0"});
    EXPECT_NE(server.first_line().find("oracle over gr00t at tcp://127.0.0.1:"), std::string::npos);
    const std::string remote = temp_dir("oracle_gr00t_" + era);
    const auto r = eval_into(remote, "gr00t://127.0.0.1:" + std::to_string(server.port()) +
                                         "?privileged=1&dtype=f8&era=" + era);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    expect_same_episodes(local, remote);
  }
}

TEST(ServeCommandTest, APrivilegedServerNeedsPrivilegedInTheReference) {
  ServerProcess server({HRIBENCH_BINARY, "serve", "--policy", "oracle", "--protocol", "openpi", "--port", "0"});
  const auto r = run_hribench("eval --tasks I1 --episodes 1 --horizon 1 --policy openpi://127.0.0.1:" +
                              std::to_string(server.port()) + " --out " + temp_dir("unprivileged"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("privileged=1"), std::string::npos) << r.output;
}

TEST(ServeCommandTest, BadOptionsAreOneLine) {
  for (const std::string args : {"--policy oracle --protocol http", "--policy nosuch", "--policy openpi://x:1",
                                 "--policy noop --port 70000"}) {
    const auto r = run_hribench("serve " + args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << args << ": " << r.output;
  }
}

}  // namespace
}  // namespace hribench::cli
