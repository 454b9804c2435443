#include "core/errors.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace hribench::core {
namespace {

TEST(InputErrorTest, MessageNamesWhereExpectedAndGot) {
  const InputError e("tasks/x.yaml:3:7 (acts.take.goal)", "a predicate", "'grasp(robot)'");
  EXPECT_STREQ(e.what(), "tasks/x.yaml:3:7 (acts.take.goal): expected a predicate, got 'grasp(robot)'");
  EXPECT_EQ(e.where(), "tasks/x.yaml:3:7 (acts.take.goal)");
  EXPECT_EQ(e.expected(), "a predicate");
  EXPECT_EQ(e.got(), "'grasp(robot)'");
}

TEST(InputErrorTest, FreeFormMessage) {
  const InputError e = InputError::Message("--out scene.png", "cannot open for writing");
  EXPECT_STREQ(e.what(), "--out scene.png: cannot open for writing");
}

TEST(EpisodeStatusTest, NamesMatchResultFiles) {
  EXPECT_EQ(to_string(EpisodeStatus::kOk), "ok");
  EXPECT_EQ(to_string(EpisodeStatus::kInvalid), "invalid");
  EXPECT_EQ(to_string(EpisodeStatus::kPolicyError), "policy_error");
}

TEST(CheckDeathTest, FailedCheckAbortsWithFileLineAndContext) {
  const int n = -3;
  EXPECT_DEATH(HRIB_CHECK(n > 0) << "n=" << n, "errors_test.cc:[0-9]+: check failed: n > 0 n=-3");
}

// The Python module's mode (docs/python.md): a failed check throws CheckError with the text it
// would print; switched back, checks abort again.
TEST(CheckDeathTest, FailedCheckThrowsWhenAsked) {
  const int n = -3;
  set_check_failure_throws(true);
  try {
    HRIB_CHECK(n > 0) << "n=" << n;
    set_check_failure_throws(false);
    FAIL() << "no exception";
  } catch (const CheckError& e) {
    set_check_failure_throws(false);
    EXPECT_THAT(e.what(), ::testing::MatchesRegex(".*errors_test.cc:[0-9]+: check failed: n > 0 n=-3"));
  }
  EXPECT_DEATH(HRIB_CHECK(n > 0), "check failed: n > 0");
}

TEST(CheckTest, PassingCheckDoesNothing) {
  int evaluated = 0;
  HRIB_CHECK(++evaluated == 1) << "never printed";
  EXPECT_EQ(evaluated, 1);
}

}  // namespace
}  // namespace hribench::core
