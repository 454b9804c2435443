// Tests of the `hribench` entry point: unknown commands and flags give one clear line and a
// non-zero exit; --version and version print provenance.

#include <gtest/gtest.h>

#include "support/run_command.h"

namespace hribench::cli {
namespace {

using ::hribench::testing::count_lines;
using ::hribench::testing::run_hribench;

TEST(MainTest, UnknownCommandIsOneLineNamingTheCommands) {
  const auto r = run_hribench("frobnicate");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("hribench: error: hribench: expected a command ("), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("version"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("got 'frobnicate'"), std::string::npos) << r.output;
}

TEST(MainTest, UnknownFlagIsOneLine) {
  const auto r = run_hribench("version --bogus");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("--bogus"), std::string::npos) << r.output;
}

TEST(MainTest, BadLogLevelIsRejected) {
  const auto r = run_hribench("--log-level loud version");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--log-level: expected one of trace, debug, info, warn, error, off, got 'loud'"),
            std::string::npos) << r.output;
}

TEST(MainTest, VersionNamesMujoco) {
  const auto r = run_hribench("version");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("MuJoCo 2.2.2"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace hribench::cli
