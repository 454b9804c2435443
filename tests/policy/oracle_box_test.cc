// The expert's box retrieval (C3): the plan read from the task script, and the geometry of
// waiting beside the box, reaching in over the rim and leaving it.

#include "policy/oracle_box.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/math.h"
#include "model/model.h"
#include "policy/oracle_plan.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::policy {
namespace {

using core::Pose;
using core::Vec3;

Pose box_at(double x, double y, double yaw = 0) {
  Pose X_WB = Pose::Identity();
  X_WB.translation = Vec3(x, y, model::kTableTopZ);
  X_WB.rotation = core::axis_angle(Vec3::UnitZ(), yaw);
  return X_WB;
}

// The Panda's home orientation: tool pointing down (z of the TCP frame along world -z).
Pose home() {
  Pose X = Pose::Identity();
  X.rotation = core::axis_angle(Vec3::UnitX(), core::kPi) * core::axis_angle(Vec3::UnitZ(), -core::kPi / 4);
  return X;
}

TEST(OracleBox, PlanWaitsNearTheBoxReachesInAfterTheLidAndLeavesHoldingTheCup) {
  const script::EpisodeSpec spec = script::sample(script::load_scenario("tasks/C3_box_retrieval.yaml"), 0);
  const std::vector<PlanStep> plan = make_plan(spec, Competence::kOracle);
  ASSERT_EQ(plan.size(), 4u);
  EXPECT_EQ(plan[0].kind, StepKind::kApproach);
  EXPECT_EQ(plan[0].object, "box");
  EXPECT_DOUBLE_EQ(plan[0].distance, 0.30);
  EXPECT_EQ(plan[1].kind, StepKind::kPick);
  EXPECT_EQ(plan[1].after, "lid.hold");
  // grasped(robot, item) and not near(robot, box, 0.20): keep the cup, get away from the box.
  EXPECT_EQ(plan[2].kind, StepKind::kLeave);
  EXPECT_EQ(plan[2].object, "item");
  EXPECT_EQ(plan[2].target, "box");
  EXPECT_DOUBLE_EQ(plan[2].distance, 0.20);
  EXPECT_EQ(to_string(plan[2].kind), "leave");
  EXPECT_EQ(plan[3].kind, StepKind::kPlace);
  EXPECT_EQ(plan[3].target, "tray");
  // Blind ignores the lid.
  EXPECT_EQ(make_plan(spec, Competence::kBlind)[1].after, "");
}

TEST(OracleBox, TheGraspKeepsTheTiltedHousingAboveTheRimAndReachesTheCupTop) {
  const Pose X_WB = box_at(0.68, 0.02);
  const double rim = oracle_box::rim_z(X_WB);
  EXPECT_NEAR(rim, model::kTableTopZ + 0.12, 1e-12);
  // A cup's own grasp height (mid-height) lies deep in the box: raised to the housing limit.
  const double cup_bottom = model::kTableTopZ + oracle_box::kWallThickness;
  const double z = oracle_box::grasp_z(X_WB, cup_bottom + 0.055);
  const double lowest = oracle_box::kHousingAboveTcp * std::cos(oracle_box::kTilt) -
                        oracle_box::kHousingHalfWidth * std::sin(oracle_box::kTilt);
  EXPECT_NEAR(z + lowest, rim + oracle_box::kHousingClearance, 1e-12);
  // ... where the fingertips are still below the cup's top (0.09 m tall).
  EXPECT_LT(z - oracle_box::kTipBelowTcp, cup_bottom + 0.09 - 0.01);
  // A grasp already higher stays.
  EXPECT_DOUBLE_EQ(oracle_box::grasp_z(X_WB, rim + 0.1), rim + 0.1);
  // Entering, the fingertips pass over the rim.
  EXPECT_NEAR(oracle_box::entry_z(X_WB) - oracle_box::kTipBelowTcp, rim + oracle_box::kTipClearance, 1e-12);
  // The grasp shifts toward the robot (the box's -x).
  const Vec3 p = oracle_box::grasp_point(box_at(0.68, 0.02, core::kPi / 2), Vec3(0.68, 0.02, 0.8));
  EXPECT_NEAR(p.x(), 0.68, 1e-12);
  EXPECT_NEAR(p.y(), 0.02 - oracle_box::kGraspShift, 1e-12);
}

TEST(OracleBox, TheRobotWaitsNearTheBoxOnTheSideAwayFromThePerson) {
  const Pose X_WB = box_at(0.68, 0.0);
  for (const double person_y : {-0.3, 0.3}) {
    const Vec3 wait = oracle_box::wait_point(X_WB, Vec3(1.2, person_y, 0.9), 0.30);
    EXPECT_NEAR((wait - oracle_box::centre(X_WB)).norm(), oracle_box::kWaitShare * 0.30, 1e-9);
    EXPECT_LT(wait.y() * person_y, 0) << person_y;   // the other side
    EXPECT_LT(wait.x(), X_WB.translation.x());       // toward the robot
    EXPECT_GT(wait.z() - oracle_box::kTipBelowTcp, oracle_box::rim_z(X_WB));
    EXPECT_FALSE(oracle_box::inside(X_WB, wait, 0.0));
  }
}

TEST(OracleBox, LeavingGoesHighEnoughToBeBeyondTheDistance) {
  const Pose X_WB = box_at(0.68, 0.0);
  for (const double dy : {0.0, 0.05, 0.3}) {
    const Vec3 tcp(0.68, dy, 0.85);
    const double z = oracle_box::exit_z(X_WB, tcp, 0.20);
    const Vec3 out(tcp.x(), tcp.y(), z);
    EXPECT_GE((out - oracle_box::centre(X_WB)).norm(), 0.20 + oracle_box::kLeaveMargin - 1e-9) << dy;
    EXPECT_GE(z, oracle_box::entry_z(X_WB)) << dy;
  }
  EXPECT_TRUE(oracle_box::inside(X_WB, Vec3(0.7, 0.05, model::kTableTopZ + 0.01), 0.0));
  EXPECT_FALSE(oracle_box::inside(X_WB, Vec3(0.7, 0.05, model::kTableTopZ + 0.13), 0.0));
  EXPECT_TRUE(oracle_box::inside(X_WB, Vec3(0.7, 0.05, model::kTableTopZ + 0.13), 0.05));
  EXPECT_FALSE(oracle_box::inside(X_WB, Vec3(0.7, 0.09, model::kTableTopZ + 0.01), 0.0));
}

TEST(OracleBox, TheFingersOpenAlongTheHingeAndTheWristLeansTowardTheRobot) {
  for (const double yaw : {0.0, 0.4, -1.2}) {
    const Pose X_WB = box_at(0.68, 0.0, yaw);
    const double a = oracle_box::finger_yaw(X_WB, home());
    EXPECT_GE(a, -core::kPi / 2);
    EXPECT_LT(a, core::kPi / 2);
    const core::Quat q = oracle_box::hand_rotation(X_WB, home());
    const Vec3 fingers = q * Vec3::UnitY();
    EXPECT_NEAR(std::abs(fingers.dot(X_WB.rotation * Vec3::UnitY())), 1.0, 1e-9) << yaw;
    // The wrist (the TCP frame's -z) tilts by kTilt toward the box's -x.
    const Vec3 up = q * Vec3(0, 0, -1);
    EXPECT_NEAR(up.z(), std::cos(oracle_box::kTilt), 1e-9) << yaw;
    EXPECT_LT(up.dot(X_WB.rotation * Vec3::UnitX()), -0.3) << yaw;
  }
}

}  // namespace
}  // namespace hribench::policy
