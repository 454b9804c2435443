// Controllers: joint targets, ee_delta differential IK, gripper, and a scripted grasp by finger
// contact only (no teleporting, no weld). Tracking, the gripper and the grasp are checked under
// the physics as built (the Euler integrator with model::servo_damping_in_joints) and under pool
// v4's (the implicit integrator with the damping in the servos alone, docs/performance.md
// "Physics").

#include "sim/control.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "model/model.h"
#include "sim/data.h"
#include "support/mujoco_fixture.h"

namespace hribench::sim {
namespace {

using ControlTest = testing::MujocoTest;
using core::Pose;
using core::Vec3;

// The physics a parameterised test runs: the scene as built, or pool v4's implicit servos.
enum class Physics { kAsBuilt, kImplicit };

model::Model build_with(Physics physics, const model::SceneSpec& spec) {
  model::Model model = model::build(spec);
  if (physics == Physics::kImplicit) {
    model.mj->opt.integrator = mjINT_IMPLICIT;
    model::servo_damping_in_servos(model);
  }
  return model;
}

class ControlPhysicsTest : public testing::MujocoTest, public ::testing::WithParamInterface<Physics> {
 protected:
  model::Model build(const model::SceneSpec& spec) const { return build_with(GetParam(), spec); }
};

INSTANTIATE_TEST_SUITE_P(Physics, ControlPhysicsTest,
                         ::testing::Values(Physics::kAsBuilt, Physics::kImplicit),
                         [](const ::testing::TestParamInfo<Physics>& param) {
                           return param.param == Physics::kAsBuilt ? "AsBuilt" : "Implicit";
                         });

// Steps `seconds` of physics.
void run(const model::Model& model, Data& data, double seconds) {
  const int n = static_cast<int>(std::lround(seconds / model::kTimestep));
  for (int i = 0; i < n; ++i) step(model, data);
}

// Moves the TCP along a straight line to `target` in `seconds`, commanding at 20 Hz.
void move_tcp(const model::Model& model, Data& data, const Pose& target, double seconds) {
  const Pose start = tcp_pose(model, data);
  const int ticks = static_cast<int>(std::lround(seconds * 20));
  for (int k = 1; k <= ticks; ++k) {
    const double s = static_cast<double>(k) / ticks;
    Pose via;
    via.translation = start.translation + s * (target.translation - start.translation);
    via.rotation = start.rotation.slerp(s, target.rotation);
    set_tcp_target(model, data, via);
    run(model, data, 0.05);
  }
}

TEST_P(ControlPhysicsTest, JointTargetsAreClampedToLimitsAndTracked) {
  const model::Model model = build(model::SceneSpec::Default());
  Data data = make_data(model);
  const model::Robot& robot = model.robot;
  ArmVector q = robot.home();
  q[0] = robot.joints[0].q_max + 2;  // beyond its limits
  q[3] = robot.joints[3].q_max + 0.5;
  q[1] = 0.3;
  set_joint_targets(model, data, q);
  EXPECT_LT(data.q_target[0], robot.joints[0].q_max);
  EXPECT_GT(data.q_target[0], robot.joints[0].q_max - 0.01);
  EXPECT_LT(data.q_target[3], robot.joints[3].q_max);
  EXPECT_DOUBLE_EQ(data.q_target[1], 0.3);
  run(model, data, 3.0);
  const ArmVector now = arm_joint_positions(model, data);
  for (size_t i = 0; i < model.robot.dof(); ++i) {
    EXPECT_NEAR(now[i], data.q_target[i], 0.01) << "joint " << i + 1;
    EXPECT_LE(now[i], model.robot.joints[i].q_max + 1e-3);
    EXPECT_GE(now[i], model.robot.joints[i].q_min - 1e-3);
  }
  ExpectNoWarnings(data.mj.get());
}

TEST_F(ControlTest, EeDeltaMovesTheTcpByTheRequestedAmount) {
  model::SceneSpec spec = model::SceneSpec::Default();
  spec.objects.clear();
  const model::Model model = model::build(spec);
  Data data = make_data(model);
  const Vec3 moves[] = {{0.03, 0, 0}, {0, 0.03, 0}, {0, 0, -0.03}, {-0.02, -0.02, 0.02}};
  for (const Vec3& dp : moves) {
    const Pose before = tcp_pose(model, data);
    EeDelta delta;
    delta.translation = dp;
    const IkResult r = apply_ee_delta(model, data, delta);
    EXPECT_LT(r.position_error, 1e-4);
    run(model, data, 0.6);
    const Pose after = tcp_pose(model, data);
    EXPECT_LT((after.translation - before.translation - dp).norm(), 1.5e-3) << dp.transpose();
    EXPECT_LT(Eigen::AngleAxisd(after.rotation * before.rotation.conjugate()).angle(), 0.01);
  }
  // A rotation about world z (yaw) of 0.3 rad, position kept.
  const Pose before = tcp_pose(model, data);
  EeDelta yaw;
  yaw.rotation = Vec3(0, 0, 0.3);
  apply_ee_delta(model, data, yaw);
  run(model, data, 0.8);
  const Pose after = tcp_pose(model, data);
  const Eigen::AngleAxisd turned(after.rotation * before.rotation.conjugate());
  EXPECT_NEAR(turned.angle(), 0.3, 0.01);
  EXPECT_NEAR(std::abs(turned.axis().z()), 1.0, 0.02);
  EXPECT_LT((after.translation - before.translation).norm(), 1.5e-3);
  ExpectNoWarnings(data.mj.get());
}

// From an observed state, the delta from the observed TCP pose (what an episode passes) sets the
// same joint targets, to the bit, as the delta from the pose the scratch computes.
TEST_F(ControlTest, EeDeltaFromTheObservedTcpPoseIsTheSame) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data a = make_data(model);
  EeDelta delta;
  delta.translation = Vec3(0.02, -0.01, 0.015);
  delta.rotation = Vec3(0, 0.05, 0.1);
  apply_ee_delta(model, a, delta);
  run(model, a, 0.3);
  observe_state(model, a);
  Data b = make_data(model);
  copy_data(model, a, b);
  const IkResult from_scratch = apply_ee_delta(model, a, delta);
  const IkResult from_observed = apply_ee_delta(model, b, delta, observed_tcp_pose(model, b));
  EXPECT_TRUE(std::equal(from_scratch.q_target.begin(), from_scratch.q_target.end(), from_observed.q_target.begin()));
  EXPECT_EQ(from_scratch.position_error, from_observed.position_error);
  EXPECT_EQ(from_scratch.rotation_error, from_observed.rotation_error);
  ExpectNoWarnings(a.mj.get());
}

TEST_F(ControlTest, EeDeltaRespectsJointLimits) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data data = make_data(model);
  // Ask for far more than the arm can reach, repeatedly.
  for (int k = 0; k < 40; ++k) {
    EeDelta delta;
    delta.translation = Vec3(0.05, 0, 0.05);
    const IkResult r = apply_ee_delta(model, data, delta);
    for (size_t i = 0; i < model.robot.dof(); ++i) {
      EXPECT_LT(r.q_target[i], model.robot.joints[i].q_max);
      EXPECT_GT(r.q_target[i], model.robot.joints[i].q_min);
    }
    run(model, data, 0.05);
  }
  run(model, data, 1.0);
  const ArmVector q = arm_joint_positions(model, data);
  for (size_t i = 0; i < model.robot.dof(); ++i) {
    EXPECT_LE(q[i], model.robot.joints[i].q_max + 2e-3) << "joint " << i + 1;
    EXPECT_GE(q[i], model.robot.joints[i].q_min - 2e-3) << "joint " << i + 1;
  }
  ExpectNoWarnings(data.mj.get());
}

TEST_P(ControlPhysicsTest, GripperOpensAndClosesToTheCommandedWidth) {
  model::SceneSpec spec = model::SceneSpec::Default();
  spec.objects.clear();
  const model::Model model = build(spec);
  Data data = make_data(model);
  EXPECT_NEAR(gripper_width(model, data), 0.08, 1e-6);
  set_gripper_width(model, data, 0.03);
  run(model, data, 0.5);
  EXPECT_NEAR(gripper_width(model, data), 0.03, 1e-3);
  // Fingers stay symmetric (coupled).
  EXPECT_NEAR(data.mj->qpos[model.finger_qpos_adr[0]], data.mj->qpos[model.finger_qpos_adr[1]], 1e-3);
  close_gripper(model, data);
  run(model, data, 0.5);
  EXPECT_LT(gripper_width(model, data), 2e-3);
  set_gripper_width(model, data, 0.5);  // clamped
  EXPECT_DOUBLE_EQ(data.gripper_width_target, 0.08);
  run(model, data, 0.5);
  EXPECT_NEAR(gripper_width(model, data), 0.08, 1e-3);
  ExpectNoWarnings(data.mj.get());
}

TEST_P(ControlPhysicsTest, ScriptedGraspLiftsTheCubeTenCentimetresAndHoldsIt) {
  const model::Model model = build(model::SceneSpec::Default());
  Data data = make_data(model);
  const int cube = model.object_index("cube");
  ASSERT_GE(cube, 0);
  const model::ObjectInfo& info = model.objects[static_cast<size_t>(cube)];
  const auto cube_position = [&] {
    const mjtNum* q = data.mj->qpos + info.qpos_adr;
    return Vec3(q[0], q[1], q[2]);
  };
  run(model, data, 0.2);
  const Vec3 start = cube_position();
  const Vec3 centre = start + Vec3(0, 0, info.half_extents.z());
  // Top-down grasp: hand z down, fingers closing along world y.
  Pose above;
  above.rotation = core::axis_angle(Vec3::UnitX(), core::kPi);
  above.translation = centre + Vec3(0, 0, 0.12);
  move_tcp(model, data, above, 1.5);
  Pose at = above;
  at.translation = centre;
  move_tcp(model, data, at, 1.0);
  run(model, data, 0.3);
  close_gripper(model, data);
  run(model, data, 0.8);
  EXPECT_GT(gripper_width(model, data), 0.045);  // stopped by the cube (0.05 m)
  Pose lifted = at;
  lifted.translation.z() += 0.10;
  move_tcp(model, data, lifted, 1.0);
  run(model, data, 0.3);
  const Vec3 held = cube_position();
  const Vec3 offset_start = held - tcp_pose(model, data).translation;
  // Held, the fingers stay on the cube's faces: with the gripper damped in the finger joints
  // under Euler the contacts went soft and the width swung between 31 and 49 mm.
  double narrowest = 1, widest = 0;
  for (int i = 0; i < 40; ++i) {
    run(model, data, 0.05);
    narrowest = std::min(narrowest, gripper_width(model, data));
    widest = std::max(widest, gripper_width(model, data));
  }
  EXPECT_GT(narrowest, 0.045);
  EXPECT_LT(widest - narrowest, 0.001);
  const Vec3 end = cube_position();
  const Vec3 offset_end = end - tcp_pose(model, data).translation;
  EXPECT_GE(end.z() - start.z(), 0.095);
  EXPECT_LT((offset_end - offset_start).norm(), 0.005);
  EXPECT_LT((end - held).norm(), 0.005);
  ExpectNoWarnings(data.mj.get());
}

// Under Euler the servos' damping kv must be added back unclamped: in the joints' damping alone
// it sits outside the servo's force limit, and joint 1 (87 N·m, kv 450 N·m·s/rad) cannot move
// faster than 87 / 450 = 0.19 rad/s. With it added back, joint 1 crosses 1 rad as fast as under
// the implicit integrator.
TEST_F(ControlTest, UnderEulerServoJointOneMovesAsFastAsTheImplicitServo) {
  const double kStep = 1.0;
  const auto seconds_to_cross = [&](const model::Model& model) {
    Data data = make_data(model);
    ArmVector q = model.robot.home();
    const double start = q[0];
    q[0] += kStep;
    set_joint_targets(model, data, q);
    for (int i = 1; i <= 2000; ++i) {
      step(model, data);
      if (arm_joint_positions(model, data)[0] > start + 0.9 * kStep) return i * model::kTimestep;
    }
    return 1e9;
  };
  const double implicit = seconds_to_cross(build_with(Physics::kImplicit, model::SceneSpec::Default()));
  ASSERT_LT(implicit, 2.0);
  model::Model model = build_with(Physics::kAsBuilt, model::SceneSpec::Default());
  EXPECT_NEAR(seconds_to_cross(model), implicit, 0.05 * implicit);
  model.servo_damping_in_joints = false;  // the damping in the joints, not added back
  EXPECT_GT(seconds_to_cross(model), 4.0);
}

}  // namespace
}  // namespace hribench::sim
