#include "eval/robot_motion.h"

#include <gtest/gtest.h>

#include "episode_builder.h"

namespace hribench::eval {
namespace {

using testing::EpisodeBuilder;

TimeSet moving(const EpisodeBuilder& b) { return moving_time(b.log(), MetricConstants{}); }

TEST(RobotMotionTest, ACommandedCloseIsMoving) {
  EpisodeBuilder b(3.0);
  b.grip(1.0, 1.5, -0.03);
  const TimeSet set = moving(b);
  ASSERT_EQ(set.size(), 1u);
  EXPECT_NEAR(set[0].from, 1.0, 1e-9);
  EXPECT_NEAR(set[0].to, 1.5, 1e-9);
}

// Fingers closed on an object (commanded shut, 0) settle over two control steps: in by 1.4 mm,
// back out by 1 mm. Both steps change the width faster than moving_gripper_rate, which read
// as a sustained motion before; only the first goes the way the robot told the gripper to.
TEST(RobotMotionTest, FingersSettlingOnAGraspAreNotMoving) {
  const MetricConstants c;
  EpisodeBuilder b(3.0);
  b.gripper_at(0, 0.05828, 0).gripper_at(1.05, 0.05690, 0).gripper_at(1.1, 0.05788, 0);
  const auto& steps = b.log().steps;
  for (size_t k : {21u, 22u}) {
    ASSERT_NEAR(steps[k].time, 1.0 + 0.05 * static_cast<double>(k - 20), 1e-9);
    EXPECT_GT(std::abs(steps[k].gripper_width - steps[k - 1].gripper_width) / 0.05, c.moving_gripper_rate);
  }
  EXPECT_TRUE(moving(b).empty());
  EXPECT_EQ(still_time(b.log(), c).size(), 2u);  // before and after the settling

  // The same widths, each commanded: the robot moved its gripper in and out.
  EpisodeBuilder told(3.0);
  told.gripper_at(0, 0.05828, 0.05828).gripper_at(1.05, 0.05690, 0.05690).gripper_at(1.1, 0.05788, 0.05788);
  const TimeSet set = moving(told);
  ASSERT_EQ(set.size(), 1u);
  EXPECT_NEAR(set[0].from, 1.0, 1e-9);
  EXPECT_NEAR(set[0].to, 1.1, 1e-9);
}

TEST(RobotMotionTest, FingersPushedOpenAgainstTheCommandAreNotMoving) {
  EpisodeBuilder b(3.0);
  b.gripper_at(0, 0.05, 0).grip(1.0, 1.5, 0.03);
  ASSERT_EQ(moving(b).size(), 1u);  // commanded open
  b.gripper_target(0, 3.0, 0);      // told to stay shut
  EXPECT_TRUE(moving(b).empty());
}

}  // namespace
}  // namespace hribench::eval
