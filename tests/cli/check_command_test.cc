#include <gtest/gtest.h>

#include <string>

#include "support/run_command.h"

namespace hribench::testing {
namespace {

TEST(CheckCommandTest, CleanScriptsExitZero) {
  const CommandResult r = run_hribench(
      "check tests/data/scripts/good/handover_h2r.yaml tests/data/scripts/good/stop_go.yaml");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output,
            "tests/data/scripts/good/handover_h2r.yaml: ok\n"
            "tests/data/scripts/good/stop_go.yaml: ok\n");
}

// Every problem of every file, one per line, then a summary; exit non-zero.
TEST(CheckCommandTest, PrintsEveryProblemAndFails) {
  const CommandResult r = run_hribench(
      "check -q tests/data/scripts/bad/many_problems.yaml tests/data/scripts/bad/tab_indentation.yaml "
      "tests/data/scripts/good/stop_go.yaml");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(count_lines(r.output), 5 + 1 + 1) << r.output;
  EXPECT_NE(r.output.find("tests/data/scripts/bad/many_problems.yaml:3:7 (role): expected instructor, "
                          "collaborator or intruder, got 'helper'\n"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("tests/data/scripts/bad/tab_indentation.yaml:21:1: expected spaces for "
                          "indentation, got a tab\n"),
            std::string::npos);
  EXPECT_NE(r.output.find("hribench check: 6 problem(s) in 2 of 3 file(s)"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("stop_go.yaml: ok"), std::string::npos);  // -q
}

// --sample prints the drawn EpisodeSpec and its hash; the same seed gives the same bytes.
TEST(CheckCommandTest, SamplePrintsTheSpecAndItsHash) {
  const std::string args = "check -q tests/data/scripts/good/handover_h2r.yaml --sample 7";
  const CommandResult a = run_hribench(args);
  const CommandResult b = run_hribench(args);
  EXPECT_EQ(a.exit_code, 0) << a.output;
  EXPECT_EQ(a.output, b.output);
  EXPECT_NE(a.output.find("\"task\": \"handover_h2r\""), std::string::npos) << a.output;
  EXPECT_NE(a.output.find("\"seed\": 7"), std::string::npos);
  const size_t hash = a.output.find("sha256 ");
  ASSERT_NE(hash, std::string::npos);
  EXPECT_EQ(a.output.size() - hash, 7 + 64 + 1U);
  EXPECT_NE(run_hribench("check -q tests/data/scripts/good/handover_h2r.yaml --sample 8").output, a.output);
}

TEST(CheckCommandTest, NeedsAFile) {
  const CommandResult r = run_hribench("check");
  EXPECT_NE(r.exit_code, 0);
  const CommandResult missing = run_hribench("check tests/data/scripts/none.yaml");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find("tests/data/scripts/none.yaml: cannot open file"), std::string::npos);
}

}  // namespace
}  // namespace hribench::testing
