// Tests of the first hour (issue 21): commands run from a folder outside the repository find
// tasks/ and pool/ through the data root (core/paths.h), task ids and names are accepted and
// listed in messages, help shows defaults, and bad values get one clear line.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
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
using ::hribench::testing::run_hribench_in;
using ::hribench::testing::run_hribench_with;

// A fresh folder outside the repository, per test and process.
std::string outside(const std::string& name) {
  const std::string dir = ::hribench::testing::temp_dir("anywhere", name);
  fs::create_directories(dir);
  return dir;
}

TEST(AnywhereTest, EvalByTaskIdFromAnotherFolder) {
  const std::string dir = outside("eval_id");
  const auto r = run_hribench_in(dir, "eval --tasks I1 --policy noop --episodes 1 --horizon 0.5 --out run");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json options = nlohmann::json::parse(std::ifstream(fs::path(dir) / "run" / "options.json"));
  // Recorded as from the repository root, whatever the working folder.
  EXPECT_EQ(options.at("tasks"), nlohmann::json::array({"tasks/I1_point_pick.yaml"}));
  fs::remove_all(dir);
}

TEST(AnywhereTest, CheckFindsTaskScriptsFromAnotherFolder) {
  const std::string dir = outside("by_name");
  const auto by_id = run_hribench_in(dir, "check --sample 3 --quiet tasks/I4_stop_go.yaml");
  ASSERT_EQ(by_id.exit_code, 0) << by_id.output;
  EXPECT_NE(by_id.output.find("sha256 "), std::string::npos) << by_id.output;
  fs::remove_all(dir);
}

TEST(AnywhereTest, RenderFindsTheTaskScriptFromAnotherFolder) {
  const std::string dir = outside("render");
  const auto r = run_hribench_in(dir, "render --task tasks/I1_point_pick.yaml --width 8 --height 8 --out x.png");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(fs::path(dir) / "x.png"));
  fs::remove_all(dir);
}

TEST(AnywhereTest, EvalOnAPoolGivenByAbsolutePathFromAnotherFolder) {
  const std::string dir = outside("pool_abs");
  // The released pool (pool/vN, N = gen::kPoolVersion).
  const std::string pool =
      (fs::path(HRIBENCH_SOURCE_DIR) / "pool" / ("v" + std::to_string(gen::kPoolVersion))).string();
  const auto r = run_hribench_in(dir, "eval --pool " + pool +
                                          " --split eval --tasks X4 --policy noop --horizon 0.5 --out run");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(fs::path(dir) / "run" / "results.json"));
  fs::remove_all(dir);
}

TEST(AnywhereTest, UnknownTaskListsIdsAndNames) {
  const std::string dir = outside("unknown_task");
  const auto r = run_hribench_in(dir, "eval --tasks Z9 --policy noop --out run");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("--tasks: expected a task id or name (C1 handover_h2r, "), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("I1 point_pick"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("X4 blocked_target), a script file or all, got 'Z9'"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

TEST(AnywhereTest, RootOptionAndVariable) {
  const std::string dir = outside("root");
  const auto bad = run_hribench_in(dir, "--root /nonexistent/hribench eval --tasks I1 --policy noop --out run");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("--root: expected a folder holding tasks/ and pool/, got '/nonexistent/hribench'"),
            std::string::npos) << bad.output;
  // An empty root (no tasks/): the message says where it looked and how to point elsewhere.
  const auto empty = run_hribench_in(dir, "--root . eval --tasks I1 --policy noop --out run");
  EXPECT_EQ(empty.exit_code, 2);
  EXPECT_NE(empty.output.find("set --root or HRIBENCH_ROOT"), std::string::npos) << empty.output;
  const auto env = run_hribench_with("cd '" + dir + "' && HRIBENCH_ROOT=/nonexistent/x ",
                                     "eval --tasks I1 --policy noop --out run");
  EXPECT_EQ(env.exit_code, 2);
  EXPECT_NE(env.output.find("HRIBENCH_ROOT: expected a folder holding tasks/ and pool/"), std::string::npos)
      << env.output;
  fs::remove_all(dir);
}

TEST(HelpTest, BareCommandAndHelpListTheCommands) {
  for (const std::string& args : {std::string(""), std::string("help")}) {
    const auto r = run_hribench(args);
    EXPECT_EQ(r.exit_code, 0) << args << ": " << r.output;
    for (const char* command : {"eval", "generate", "render", "check", "motion", "report", "bench"}) {
      EXPECT_NE(r.output.find(command), std::string::npos) << args << ": " << r.output;
    }
  }
}

TEST(HelpTest, CommandHelpShowsDefaultsAndTasks) {
  const auto r = run_hribench("help generate");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("--candidates"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("150"), std::string::npos) << r.output;  // the default
  EXPECT_NE(r.output.find("Tasks: C1 handover_h2r,"), std::string::npos) << r.output;
  const auto unknown = run_hribench("help frobnicate");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.output.find("hribench help: expected a command ("), std::string::npos) << unknown.output;
}

TEST(HelpTest, EvalListsTasksAndPoliciesMotionListsPrimitives) {
  const auto eval = run_hribench("help eval");
  EXPECT_EQ(eval.exit_code, 0) << eval.output;
  EXPECT_NE(eval.output.find("Tasks: C1 handover_h2r,"), std::string::npos) << eval.output;
  const size_t policies = eval.output.find("\nPolicies: ");
  ASSERT_NE(policies, std::string::npos) << eval.output;
  for (const char* name : {"blind", "noop", "oracle", "random", "reactive"}) {
    EXPECT_NE(eval.output.find(name, policies), std::string::npos) << name << "\n" << eval.output;
  }
  const auto motion = run_hribench("help motion");
  EXPECT_EQ(motion.exit_code, 0) << motion.output;
  EXPECT_NE(motion.output.find("Primitives: idle, walk_to, reach,"), std::string::npos) << motion.output;
}

TEST(MessagesTest, NegativeSeedIsRefused) {
  const auto r = run_hribench("generate --tasks I1 --seed -1 --out /tmp/never");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("--seed"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists("/tmp/never"));
}

TEST(MessagesTest, GenerateOutThatIsAFileOrAnEvalRun) {
  const std::string dir = outside("gen_out");
  std::ofstream(fs::path(dir) / "file.txt") << "x";
  const auto file = run_hribench_in(dir, "generate --tasks I1 --candidates 2 --adapt 1 --eval 1 --test 0 "
                                         "--executable-by none --quiet --out file.txt");
  EXPECT_EQ(file.exit_code, 2);
  EXPECT_NE(file.output.find("--out: expected a folder for the pool, got 'file.txt', a file"), std::string::npos)
      << file.output;
  fs::create_directories(fs::path(dir) / "run");
  std::ofstream(fs::path(dir) / "run" / "episodes.jsonl") << "";
  const auto run = run_hribench_in(dir, "generate --tasks I1 --candidates 2 --adapt 1 --eval 1 --test 0 "
                                        "--executable-by none --quiet --out run");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.output.find("run: holds an evaluation run (episodes.jsonl / results.json), not a pool"),
            std::string::npos) << run.output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hribench::cli
