// The Panda's flange pose from MuJoCo against an independent modified-DH computation written
// here from robots.md's table (Craig: T_{i-1,i} = RotX(alpha_{i-1}) TransX(a_{i-1}) RotZ(q_i)
// TransZ(d_i)).

#include <array>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/rng.h"
#include "model/model.h"
#include "support/mujoco_fixture.h"

namespace hribench::model {
namespace {

using PandaTest = testing::MujocoTest;

Eigen::Isometry3d dh_flange(const std::array<double, 7>& q) {
  // robots.md: a (m), d (m), alpha (rad) for joints 1..7 and the flange.
  const double pi = 3.14159265358979323846;
  const double table[8][3] = {{0, 0.333, 0},       {0, 0, -pi / 2},        {0, 0.316, pi / 2},
                              {0.0825, 0, pi / 2}, {-0.0825, 0.384, -pi / 2}, {0, 0, pi / 2},
                              {0.088, 0, pi / 2},  {0, 0.107, 0}};
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(Eigen::Vector3d(0, 0, 0.75));  // base on the table top
  for (size_t i = 0; i < 8; ++i) {
    const double theta = i < 7 ? q[i] : 0.0;
    T.rotate(Eigen::AngleAxisd(table[i][2], Eigen::Vector3d::UnitX()));
    T.translate(Eigen::Vector3d(table[i][0], 0, 0));
    T.rotate(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()));
    T.translate(Eigen::Vector3d(0, 0, table[i][1]));
  }
  return T;
}

TEST_F(PandaTest, FlangeMatchesModifiedDhOverRandomConfigurations) {
  SceneSpec spec;
  spec.human.present = false;
  const Model model = build(spec);
  const mjModel* m = model.m();
  mjData* d = mj_makeData(m);
  core::Rng rng(7);
  double worst_position = 0;
  double worst_angle = 0;
  for (int sample = 0; sample < 500; ++sample) {
    std::array<double, 7> q{};
    for (size_t i = 0; i < 7; ++i) {
      q[i] = rng.uniform(model.robot.joints[i].q_min, model.robot.joints[i].q_max);
      d->qpos[model.arm_qpos_adr[i]] = q[i];
    }
    mj_kinematics(m, d);
    const Eigen::Isometry3d expected = dh_flange(q);
    const int s = model.flange_site;
    const Eigen::Vector3d p(d->site_xpos[3 * s], d->site_xpos[3 * s + 1], d->site_xpos[3 * s + 2]);
    Eigen::Matrix3d R;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R(r, c) = d->site_xmat[9 * s + 3 * r + c];
    worst_position = std::max(worst_position, (p - expected.translation()).norm());
    worst_angle = std::max(worst_angle, Eigen::AngleAxisd(R * expected.rotation().transpose()).angle());
  }
  EXPECT_LT(worst_position, 1e-3);
  EXPECT_LT(worst_angle, 1e-6);
  ExpectNoWarnings(d);
  mj_deleteData(d);
}

TEST_F(PandaTest, HandIsMountedRotatedAboutTheFlangeAndTcpIsAlongItsZ) {
  SceneSpec spec;
  spec.human.present = false;
  const Model model = build(spec);
  const mjModel* m = model.m();
  mjData* d = mj_makeData(m);
  mj_resetDataKeyframe(m, d, 0);
  mj_kinematics(m, d);
  const int h = model.hand_body;
  const int s = model.flange_site;
  const int t = model.tcp_site;
  // Hand origin at the flange; TCP 0.1034 m along the hand's z axis.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(d->xpos[3 * h + k], d->site_xpos[3 * s + k], 1e-9);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(d->site_xpos[3 * t + k] - d->xpos[3 * h + k], 0.1034 * d->xmat[9 * h + 3 * k + 2],
                1e-9);
  // Hand x axis = flange x rotated -45 deg about the flange z axis.
  Eigen::Matrix3d flange, hand;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      flange(r, c) = d->site_xmat[9 * s + 3 * r + c];
      hand(r, c) = d->xmat[9 * h + 3 * r + c];
    }
  const Eigen::AngleAxisd rel(flange.transpose() * hand);
  EXPECT_NEAR(rel.angle(), 3.14159265358979 / 4, 1e-6);
  EXPECT_NEAR(std::abs(rel.axis().z()), 1.0, 1e-6);
  EXPECT_LT((flange.transpose() * hand * Eigen::Vector3d::UnitX() -
             Eigen::AngleAxisd(-3.14159265358979 / 4, Eigen::Vector3d::UnitZ()) *
                 Eigen::Vector3d::UnitX())
                .norm(),
            1e-6);
  ExpectNoWarnings(d);
  mj_deleteData(d);
}

TEST_F(PandaTest, LimitsMassesAndActuatorsFollowTheReference) {
  SceneSpec spec;
  spec.human.present = false;
  const Model model = build(spec);
  const mjModel* m = model.m();
  const double masses[8] = {0.629769, 4.970684, 0.646926, 3.228604,
                            3.587895, 1.225946, 1.666555, 0.735522};
  for (size_t i = 0; i < 8; ++i)
    EXPECT_NEAR(m->body_mass[model.link_body[i]], masses[i], 1e-6) << "link" << i;
  EXPECT_NEAR(m->body_mass[model.hand_body], 0.73, 1e-6);
  for (size_t i = 0; i < 2; ++i) EXPECT_NEAR(m->body_mass[model.finger_body[i]], 0.015, 1e-6);
  // robots.md's joint position and torque limits.
  const double q_min[7] = {-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973};
  const double q_max[7] = {2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973};
  const double tau_max[7] = {87, 87, 87, 87, 12, 12, 12};
  ASSERT_EQ(model.robot.name, "panda");
  ASSERT_EQ(model.robot.dof(), 7u);
  ASSERT_EQ(model.arm_joint.size(), 7u);
  ASSERT_EQ(model.link_body.size(), 8u);
  for (size_t i = 0; i < 7; ++i) {
    const int j = model.arm_joint[i];
    EXPECT_EQ(m->jnt_limited[j], 1);
    EXPECT_DOUBLE_EQ(m->jnt_range[2 * j], q_min[i]);
    EXPECT_DOUBLE_EQ(m->jnt_range[2 * j + 1], q_max[i]);
    const int a = model.arm_actuator[i];
    EXPECT_DOUBLE_EQ(m->actuator_forcerange[2 * a + 1], tau_max[i]);
    EXPECT_DOUBLE_EQ(m->actuator_forcerange[2 * a], -tau_max[i]);
  }
  EXPECT_DOUBLE_EQ(model.robot.gripper.max_width(), 0.08);
  for (size_t i = 0; i < 2; ++i) {
    const int j = model.finger_joint[i];
    EXPECT_DOUBLE_EQ(m->jnt_range[2 * j], 0.0);
    EXPECT_DOUBLE_EQ(m->jnt_range[2 * j + 1], 0.04);
  }
}

}  // namespace
}  // namespace hribench::model
