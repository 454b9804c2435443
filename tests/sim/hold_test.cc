#include "sim/hold.h"

#include <cmath>

#include <gtest/gtest.h>

#include "human/arm_ik.h"
#include "model/model.h"
#include "sim/data.h"
#include "support/mujoco_fixture.h"

namespace hribench::sim {
namespace {

using HoldTest = testing::MujocoTest;
using core::Pose;
using core::Vec3;

Pose object_pose(const model::Model& model, const Data& data, int object) {
  const mjtNum* q = data.mj->qpos + model.objects[static_cast<size_t>(object)].qpos_adr;
  Pose X;
  X.translation = Vec3(q[0], q[1], q[2]);
  X.rotation = core::quat_from_wxyz(q + 3).normalized();
  return X;
}

// A pose with the right arm raised forward (shoulder rotated about the body's y axis) and the
// person standing at x.
human::SkeletonPose reaching(const model::Model& model, double x, double raise) {
  human::SkeletonPose pose = human::SkeletonPose::Standing(model.skeleton, x, 0.0, core::kPi);
  pose.local[static_cast<size_t>(human::index(human::Joint::kRightShoulder))] =
      core::axis_angle(Vec3::UnitY(), -raise);
  return pose;
}

human::SkeletonPose blend(const human::SkeletonPose& a, const human::SkeletonPose& b, double s) {
  human::SkeletonPose p = a;
  p.X_WP.translation = a.X_WP.translation + s * (b.X_WP.translation - a.X_WP.translation);
  p.X_WP.rotation = a.X_WP.rotation.slerp(s, b.X_WP.rotation);
  for (size_t j = 0; j < human::kNumJoints; ++j) p.local[j] = a.local[j].slerp(s, b.local[j]);
  return p;
}

model::SceneSpec held_cube_scene() {
  model::SceneSpec spec;
  model::ObjectSpec cube;
  cube.kind = "cube";
  cube.name = "cube";
  cube.held_by = human::Side::kRight;
  spec.objects.push_back(cube);
  return spec;
}

TEST_F(HoldTest, HeldObjectFollowsTheHandAndFallsOntoTheTableWhenReleased) {
  const model::Model model = model::build(held_cube_scene());
  Data data = make_data(model);
  ASSERT_EQ(held_object(data, human::Side::kRight), 0);
  EXPECT_EQ(held_object(data, human::Side::kLeft), std::nullopt);
  const auto target = [&] { return palm_pose(model, data, human::Side::kRight) * model.objects[0].X_palm_hold; };
  EXPECT_LT((object_pose(model, data, 0).translation - target().translation).norm(), 1e-9);

  // Walk to the table and raise the arm over it in 1.5 s; the cube follows.
  const human::SkeletonPose from = model.human_start;
  const human::SkeletonPose to = reaching(model, 1.25, core::deg_to_rad(70));
  double worst = 0;
  const int steps = 750;
  for (int i = 1; i <= steps; ++i) {
    set_human_pose(model, data, blend(from, to, static_cast<double>(i) / steps));
    step(model, data);
    worst = std::max(worst, (object_pose(model, data, 0).translation - target().translation).norm());
  }
  for (int i = 0; i < 250; ++i) step(model, data);
  const Pose settled = object_pose(model, data, 0);
  EXPECT_LT(worst, 0.02);
  EXPECT_LT((settled.translation - target().translation).norm(), 0.003);
  EXPECT_LT(Eigen::AngleAxisd(settled.rotation * target().rotation.conjugate()).angle(), 0.02);
  const Vec3 moved = settled.translation - model.objects[0].X_W_start.translation;
  EXPECT_GT(moved.norm(), 0.3);  // it really travelled with the hand
  ASSERT_GT(settled.translation.z(), model::kTableTopZ + 0.1);
  ASSERT_LT(settled.translation.x(), model::kTableXMax - 0.05);

  // Let go: it falls onto the table and comes to rest there.
  release_by_human(model, data, human::Side::kRight);
  EXPECT_EQ(held_object(data, human::Side::kRight), std::nullopt);
  for (int i = 0; i < 1000; ++i) step(model, data);
  const Pose fallen = object_pose(model, data, 0);
  const mjtNum* v = data.mj->qvel + model.objects[0].dof_adr;
  EXPECT_LT(fallen.translation.z(), model::kTableTopZ + 0.05);
  EXPECT_GT(fallen.translation.z(), model::kTableTopZ - 0.005);
  EXPECT_LT(Vec3(v[0], v[1], v[2]).norm(), 0.01);
  ExpectNoWarnings(data.mj.get());
}

TEST_F(HoldTest, GraspCapturesTheCurrentRelativePose) {
  model::SceneSpec spec = model::SceneSpec::Default();
  const model::Model model = model::build(spec);
  Data data = make_data(model);
  const int cube = model.object_index("cube");
  // The hand holds the cube where it is (far from the hand); moving the human moves the cube
  // by the same displacement.
  grasp_by_human(model, data, human::Side::kLeft, cube);
  const Pose before = object_pose(model, data, cube);
  human::SkeletonPose pose = model.human_start;
  const human::SkeletonPose start = pose;
  pose.X_WP.translation += Vec3(0, 0, 0.1);
  for (int i = 1; i <= 250; ++i) {
    set_human_pose(model, data, blend(start, pose, i / 250.0));
    step(model, data);
  }
  for (int i = 0; i < 250; ++i) step(model, data);
  const Pose after = object_pose(model, data, cube);
  EXPECT_LT((after.translation - before.translation - Vec3(0, 0, 0.1)).norm(), 0.003);
  // Grasping with the other hand moves the hold to that hand.
  grasp_by_human(model, data, human::Side::kRight, cube);
  EXPECT_EQ(held_object(data, human::Side::kLeft), std::nullopt);
  EXPECT_EQ(held_object(data, human::Side::kRight), cube);
  ExpectNoWarnings(data.mj.get());
}

// `pose` with the palm centre of `side` at p (arm IK; a few corrections for the wrist-palm
// offset; the spine leans for far targets).
human::SkeletonPose palm_at(const model::Model& model, human::SkeletonPose pose, human::Side side,
                            const Vec3& p, bool lean = true) {
  if (lean) {
    const double angle = human::lean_for_reach(model.skeleton, pose, side, p, 0.85, 0.8, Vec3::UnitX());
    human::lean_spine(model.skeleton, pose, Vec3::UnitX(), angle);
  }
  Vec3 wrist_target = p;
  for (int k = 0; k < 4; ++k) {
    human::ArmTarget target;
    target.wrist = wrist_target;
    human::solve_arm(model.skeleton, pose, side, target);
    const auto X = human::forward_kinematics(model.skeleton, pose);
    const Vec3 palm = human::palm_centre(model.skeleton, X[static_cast<size_t>(human::index(human::wrist(side)))]);
    wrist_target += p - palm;
  }
  return pose;
}

TEST_F(HoldTest, TwoHandsLiftAPlankEndByPointHoldsWhileTheOtherEndRests) {
  model::SceneSpec spec;
  model::PlatformSpec support;
  support.name = "support";
  support.x = 0.62;
  support.y = 0.0;
  support.length = 0.5;
  support.width = 0.12;
  support.height = 0.08;
  spec.platforms = {support};
  model::ObjectSpec plank;
  plank.kind = "plank";
  plank.name = "plank";
  plank.x = 0.62;
  plank.on = "support";
  spec.objects.push_back(plank);
  spec.human.x = 1.2;
  const model::Model model = model::build(spec);
  Data data = make_data(model);
  // Both palms just above the person's end (x 0.90, top at z 0.87), 10 cm apart.
  const auto hands_at = [&](double z) {
    human::SkeletonPose pose = palm_at(model, model.human_start, human::Side::kLeft, Vec3(0.90, -0.05, z));
    return palm_at(model, pose, human::Side::kRight, Vec3(0.90, 0.05, z), false);
  };
  const human::SkeletonPose grip = hands_at(0.88);
  for (int i = 1; i <= 500; ++i) {
    set_human_pose(model, data, blend(model.human_start, grip, i / 500.0));
    step(model, data);
  }
  grasp_point_by_human(model, data, human::Side::kLeft, 0);
  grasp_point_by_human(model, data, human::Side::kRight, 0);
  EXPECT_EQ(held_object(data, human::Side::kLeft), 0);
  EXPECT_EQ(held_object(data, human::Side::kRight), 0);
  // Lift the hands 15 cm in 1.5 s and hold 0.5 s.
  for (int i = 1; i <= 750; ++i) {
    set_human_pose(model, data, hands_at(0.88 + 0.15 * i / 750.0));
    step(model, data);
  }
  for (int i = 0; i < 250; ++i) step(model, data);
  const Pose X = object_pose(model, data, 0);
  const Vec3 along = X.rotation * Vec3::UnitX();
  const Vec3 person_end = X.translation + Vec3(0, 0, 0.02) + 0.28 * along;
  const Vec3 robot_end = X.translation + Vec3(0, 0, 0.02) - 0.28 * along;
  EXPECT_NEAR(person_end.z(), 0.85 + 0.15, 0.03);
  EXPECT_NEAR(robot_end.z(), 0.85, 0.03);                   // pivots on the support
  EXPECT_LT(std::abs((X.rotation * Vec3::UnitY()).z()), 0.05);  // two grips: no roll
  // Released, it falls back onto the support.
  release_by_human(model, data, human::Side::kLeft);
  release_by_human(model, data, human::Side::kRight);
  for (int i = 0; i < 1000; ++i) step(model, data);
  EXPECT_NEAR(object_pose(model, data, 0).translation.z(), 0.83, 0.01);
  ExpectNoWarnings(data.mj.get());
}

TEST_F(HoldTest, AHandLiftsABoxLidAndLetsItClose) {
  model::SceneSpec spec;
  model::ObjectSpec box;
  box.kind = "box";
  box.name = "box";
  box.x = 0.9;
  spec.objects.push_back(box);
  spec.human.x = 1.2;
  const model::Model model = model::build(spec);
  Data data = make_data(model);
  const model::ObjectInfo& info = model.objects[0];
  const int hinge_q = model.m()->jnt_qposadr[info.lid_joint];
  const auto lid_angle = [&] { return data.mj->qpos[hinge_q]; };
  // The lid's free edge (centre) at opening angle a: hinge at the top of the +x wall, lid
  // length 2 hx; opening rotates about +y.
  const double hx = info.half_extents.x();
  const Vec3 hinge = info.X_W_start.translation + Vec3(hx, 0, 0.12 + 0.008);
  const auto edge = [&](double a) -> Vec3 { return hinge + Vec3(-2 * hx * std::cos(a), 0, 2 * hx * std::sin(a)); };
  const auto hand_at = [&](const Vec3& p) { return palm_at(model, model.human_start, human::Side::kRight, p); };
  // Reach to the closed lid's edge, take it, lift it along its arc to 80 degrees.
  const human::SkeletonPose from = model.human_start;
  const human::SkeletonPose grasp = hand_at(edge(0.02));
  for (int i = 1; i <= 500; ++i) {
    set_human_pose(model, data, blend(from, grasp, i / 500.0));
    step(model, data);
  }
  ASSERT_LT((palm_pose(model, data, human::Side::kRight).translation - edge(0.02)).norm(), 0.02);
  grasp_lid_by_human(model, data, human::Side::kRight, 0);
  EXPECT_EQ(held_object(data, human::Side::kRight), 0);
  const double open = core::deg_to_rad(70);
  for (int i = 1; i <= 750; ++i) {
    set_human_pose(model, data, hand_at(edge(0.02 + (open - 0.02) * i / 750.0)));
    step(model, data);
  }
  for (int i = 0; i < 250; ++i) step(model, data);
  EXPECT_NEAR(lid_angle(), open, 0.15);
  // The box itself stays on the table.
  const Pose box_pose = object_pose(model, data, 0);
  EXPECT_LT((box_pose.translation - info.X_W_start.translation).norm(), 0.01);
  release_by_human(model, data, human::Side::kRight);
  for (int i = 0; i < 1000; ++i) step(model, data);
  EXPECT_LT(lid_angle(), 0.05);
  ExpectNoWarnings(data.mj.get());
}

}  // namespace
}  // namespace hribench::sim
