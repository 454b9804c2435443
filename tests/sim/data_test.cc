#include "sim/data.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "model/model.h"
#include "sim/control.h"
#include "support/mujoco_fixture.h"

namespace hribench::sim {
namespace {

using DataTest = testing::MujocoTest;
using core::Vec3;

// Steps `seconds` of physics.
void run(const model::Model& model, Data& data, double seconds) {
  const int steps = static_cast<int>(std::lround(seconds / model::kTimestep));
  for (int i = 0; i < steps; ++i) step(model, data);
}

TEST_F(DataTest, HomePoseIsCollisionFreeAndStableForTwoSeconds) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data data = make_data(model);
  const mjModel* m = model.m();
  const mjData* d = data.mj.get();
  // No robot geom touches anything at home.
  for (int c = 0; c < d->ncon; ++c) {
    const auto& t1 = model.geom_tags[static_cast<size_t>(d->contact[c].geom1)];
    const auto& t2 = model.geom_tags[static_cast<size_t>(d->contact[c].geom2)];
    EXPECT_FALSE(t1.is_robot() || t2.is_robot())
        << mj_id2name(m, mjOBJ_GEOM, d->contact[c].geom1) << " - "
        << mj_id2name(m, mjOBJ_GEOM, d->contact[c].geom2);
  }
  const core::Pose tcp0 = tcp_pose(model, data);
  std::vector<Vec3> objects0;
  for (const auto& o : model.objects)
    objects0.emplace_back(d->qpos[o.qpos_adr], d->qpos[o.qpos_adr + 1], d->qpos[o.qpos_adr + 2]);
  run(model, data, 2.0);
  EXPECT_NEAR(data.time(), 2.0, 1e-9);
  const ArmVector q = arm_joint_positions(model, data);
  for (size_t i = 0; i < model.robot.dof(); ++i) EXPECT_NEAR(q[i], model.robot.joints[i].home, 1e-3) << i;
  EXPECT_LT((tcp_pose(model, data).translation - tcp0.translation).norm(), 1e-3);
  EXPECT_NEAR(gripper_width(model, data), 0.08, 1e-4);
  for (size_t k = 0; k < model.objects.size(); ++k) {
    const auto& o = model.objects[k];
    const Vec3 p(d->qpos[o.qpos_adr], d->qpos[o.qpos_adr + 1], d->qpos[o.qpos_adr + 2]);
    EXPECT_LT((p - objects0[k]).norm(), 2e-3) << o.name;
    EXPECT_LT(std::abs(d->qvel[o.dof_adr + 2]), 1e-3) << o.name;
  }
  EXPECT_EQ(warning_count(data), 0);
  EXPECT_EQ(warning_summary(data), "");
  ExpectNoWarnings(d);
}

TEST_F(DataTest, EveryObjectKindRestsStablyOnTheTable) {
  model::SceneSpec spec;
  spec.human.present = false;
  const char* kinds[] = {"cube", "cup", "bottle", "plate", "bin", "tray", "box", "plank"};
  const double xs[] = {0.3, 0.3, 0.3, 0.6, 0.6, 0.85, 0.88, 0.55};
  const double ys[] = {-0.35, -0.15, 0.05, -0.35, -0.05, 0.2, -0.25, 0.42};
  for (size_t i = 0; i < 8; ++i) {
    model::ObjectSpec o;
    o.kind = kinds[i];
    o.x = xs[i];
    o.y = ys[i];
    spec.objects.push_back(o);
  }
  const model::Model model = model::build(spec);
  Data data = make_data(model);
  run(model, data, 2.0);
  const mjData* d = data.mj.get();
  for (const auto& o : model.objects) {
    const Vec3 p(d->qpos[o.qpos_adr], d->qpos[o.qpos_adr + 1], d->qpos[o.qpos_adr + 2]);
    EXPECT_LT((p - o.X_W_start.translation).norm(), 2e-3) << o.name;
    const core::Quat r = core::quat_from_wxyz(d->qpos + o.qpos_adr + 3);
    EXPECT_LT(Eigen::AngleAxisd(r * o.X_W_start.rotation.conjugate()).angle(), 0.01) << o.name;
  }
  // The box lid stays closed.
  EXPECT_LT(std::abs(d->qpos[model.m()->jnt_qposadr[model.objects[6].lid_joint]]), 0.01);
  ExpectNoWarnings(d);
}

TEST_F(DataTest, SetHumanPoseMovesTheMocapBodiesAtTheNextStep) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data data = make_data(model);
  human::SkeletonPose pose = model.human_start;
  pose.X_WP.translation += Vec3(0, 0.3, 0);
  set_human_pose(model, data, pose);
  EXPECT_TRUE(data.human_pose_dirty);
  step(model, data);
  EXPECT_FALSE(data.human_pose_dirty);
  const auto X = human::forward_kinematics(model.skeleton, pose);
  for (size_t j = 0; j < human::kNumJoints; ++j) {
    const int mocap = model.human_mocap[j];
    const Vec3 p(data.mj->mocap_pos[3 * mocap], data.mj->mocap_pos[3 * mocap + 1],
                 data.mj->mocap_pos[3 * mocap + 2]);
    EXPECT_LT((p - X[j].translation).norm(), 1e-12);
  }
  ExpectNoWarnings(data.mj.get());
}

// prepare_step gives mjData every input of the step (the person posed, the arm's gravity
// compensation from the last forward pass) and leaves the state alone; step() is prepare_step
// then mj_step, bit for bit.
TEST_F(DataTest, PrepareStepSetsTheInputsAndStepIsItThenMjStep) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data a = make_data(model);
  Data b = make_data(model);
  human::SkeletonPose pose = model.human_start;
  pose.X_WP.translation += Vec3(0, 0.3, 0);
  for (Data* d : {&a, &b}) set_human_pose(model, *d, pose);
  const std::vector<mjtNum> qpos(a.mj->qpos, a.mj->qpos + model.m()->nq);
  prepare_step(model, a);
  EXPECT_FALSE(a.human_pose_dirty);
  EXPECT_TRUE(std::equal(qpos.begin(), qpos.end(), a.mj->qpos));
  // At rest (qvel 0) the servos' damping adds nothing: the compensation is the bias forces.
  double compensation = 0;
  for (const int dof : model.arm_dof_adr) {
    EXPECT_EQ(a.mj->qfrc_applied[dof], a.mj->qfrc_bias[dof]) << "dof " << dof;
    compensation += std::abs(a.mj->qfrc_applied[dof]);
  }
  EXPECT_GT(compensation, 1.0);  // N m: the shoulder and elbow hold the arm up
  mj_step(model.m(), a.mj.get());
  step(model, b);
  for (int i = 0; i < model.m()->nv; ++i) EXPECT_EQ(a.mj->qvel[i], b.mj->qvel[i]) << "dof " << i;
  ExpectNoWarnings(a.mj.get());
}

// The IK scratch is made without MuJoCo's constraint arena, and its kinematics, centres of mass
// and Jacobians are those of a whole mjData to the bit.
TEST_F(DataTest, TheIkScratchLeavesOutTheConstraintArenaAndComputesTheSame) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data data = make_data(model);
  const mjModel* m = model.m();
  EXPECT_LT(data.scratch->nbuffer * 10, data.mj->nbuffer)
      << "scratch " << data.scratch->nbuffer << " bytes, state " << data.mj->nbuffer;
  ArmVector q = model.robot.home();
  q[1] += 0.3;
  set_joint_targets(model, data, q);
  for (int i = 0; i < 40; ++i) step(model, data);  // the arm moving
  const MjDataPtr whole(mj_makeData(m));
  mju_copy(whole->qpos, data.mj->qpos, m->nq);
  mj_kinematics(m, whole.get());
  mj_comPos(m, whole.get());
  std::vector<mjtNum> jacp(static_cast<size_t>(3 * m->nv)), jacr(jacp.size());
  mj_jacSite(m, whole.get(), jacp.data(), jacr.data(), model.tcp_site);
  double speed = 0;
  for (int r = 0; r < 3; ++r) {
    double v = 0;
    for (int c = 0; c < m->nv; ++c) v += jacp[static_cast<size_t>(r * m->nv + c)] * data.mj->qvel[c];
    speed += v * v;
  }
  EXPECT_GT(std::sqrt(speed), 0.01);  // m/s
  EXPECT_EQ(tcp_speed(model, data), std::sqrt(speed));
  const core::Vec3 p_whole(whole->site_xpos[3 * model.tcp_site], whole->site_xpos[3 * model.tcp_site + 1],
                           whole->site_xpos[3 * model.tcp_site + 2]);
  EXPECT_TRUE(tcp_pose(model, data).translation == p_whole);
  EXPECT_TRUE(std::equal(data.scratch->subtree_com, data.scratch->subtree_com + 3 * m->nbody, whole->subtree_com));
  ExpectNoWarnings(data.mj.get());
}

// observe_state gives the frames forward() gives for the state a physics step left (bit for
// bit: the same MuJoCo functions on the same state) and changes nothing the next step starts
// from, where forward() refreshes the warm start and the bias forces.
TEST_F(DataTest, ObserveStateGivesForwardsFramesAndChangesNothingTheNextStepStartsFrom) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data observed = make_data(model);
  human::SkeletonPose pose = model.human_start;
  pose.X_WP.translation += Vec3(0, 0.3, 0);
  ArmVector q = model.robot.home();
  q[0] += 0.4;
  set_joint_targets(model, observed, q);
  set_human_pose(model, observed, pose);
  run(model, observed, 0.2);  // the arm turning, the person moved
  Data forwarded = make_data(model);
  copy_data(model, observed, forwarded);
  const mjModel* m = model.m();
  const mjData* o = observed.mj.get();
  const std::vector<mjtNum> qpos(o->qpos, o->qpos + m->nq);
  const std::vector<mjtNum> warmstart(o->qacc_warmstart, o->qacc_warmstart + m->nv);
  const std::vector<mjtNum> bias(o->qfrc_bias, o->qfrc_bias + m->nv);
  const int ncon = o->ncon;
  observe_state(model, observed);
  forward(model, forwarded);
  const mjData* f = forwarded.mj.get();
  const auto same = [](const mjtNum* a, const mjtNum* b, int n) { return std::memcmp(a, b, sizeof(mjtNum) * n) == 0; };
  EXPECT_TRUE(same(o->xpos, f->xpos, 3 * m->nbody));
  EXPECT_TRUE(same(o->xquat, f->xquat, 4 * m->nbody));
  EXPECT_TRUE(same(o->geom_xpos, f->geom_xpos, 3 * m->ngeom));
  EXPECT_TRUE(same(o->geom_xmat, f->geom_xmat, 9 * m->ngeom));
  EXPECT_TRUE(same(o->site_xpos, f->site_xpos, 3 * m->nsite));
  EXPECT_TRUE(same(o->cam_xpos, f->cam_xpos, 3 * m->ncam));
  EXPECT_TRUE(same(o->subtree_com, f->subtree_com, 3 * m->nbody));
  EXPECT_TRUE(same(o->cvel, f->cvel, 6 * m->nbody));
  EXPECT_TRUE(tcp_pose(model, observed).translation == tcp_pose(model, forwarded).translation);
  // Either way the TCP pose in the data's own kinematics is the scratch's, to the bit.
  for (Data* data : {&observed, &forwarded}) {
    const core::Pose scratch = tcp_pose(model, *data);
    const core::Pose own = observed_tcp_pose(model, *data);
    EXPECT_TRUE(own.translation == scratch.translation);
    EXPECT_TRUE(own.rotation.coeffs() == scratch.rotation.coeffs());
  }
  // What the next physics step starts from is as the last one left it; forward() changed it.
  EXPECT_TRUE(std::equal(qpos.begin(), qpos.end(), o->qpos));
  EXPECT_TRUE(std::equal(warmstart.begin(), warmstart.end(), o->qacc_warmstart));
  EXPECT_TRUE(std::equal(bias.begin(), bias.end(), o->qfrc_bias));
  EXPECT_EQ(o->ncon, ncon);
  EXPECT_FALSE(std::equal(warmstart.begin(), warmstart.end(), f->qacc_warmstart));
  EXPECT_FALSE(std::equal(bias.begin(), bias.end(), f->qfrc_bias));
  ExpectNoWarnings(o);
}

// The hands' shapes ride in mjData::userdata for the renderers (model::kHandShapeValues).
TEST_F(DataTest, SetHumanPoseGivesTheRenderersTheHandShapes) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data data = make_data(model);
  human::SkeletonPose pose = model.human_start;
  pose.hands[0] = {0.75, 0};
  pose.hands[1] = {0.2, 1};  // the right hand points
  set_human_pose(model, data, pose);
  step(model, data);
  const std::vector<double> shapes(data.mj->userdata, data.mj->userdata + model::kHandShapeValues);
  EXPECT_EQ(shapes, (std::vector<double>{0.75, 0, 0.2, 1}));
  // Reset shows the start pose's (open) hands again.
  reset(model, data);
  forward(model, data);
  EXPECT_EQ(std::vector<double>(data.mj->userdata, data.mj->userdata + model::kHandShapeValues),
            (std::vector<double>{0, 0, 0, 0}));
  ExpectNoWarnings(data.mj.get());
}

TEST_F(DataTest, ResetRestoresTheStartStateAndIsDeterministic) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data a = make_data(model);
  Data b = make_data(model);
  const int nq = model.m()->nq;
  std::vector<mjtNum> qpos0(a.mj->qpos, a.mj->qpos + nq);
  // Disturb a, then reset it.
  ArmVector q = model.robot.home();
  q[0] = 0.5;
  set_joint_targets(model, a, q);
  human::SkeletonPose pose = model.human_start;
  pose.X_WP.translation.x() -= 0.2;
  set_human_pose(model, a, pose);
  run(model, a, 200);
  reset(model, a);
  EXPECT_EQ(a.time(), 0.0);
  EXPECT_EQ(std::memcmp(a.mj->qpos, qpos0.data(), sizeof(mjtNum) * static_cast<size_t>(nq)), 0);
  EXPECT_EQ(a.q_target, model.robot.home());
  // Same commands from the same state: bit-identical trajectories.
  for (Data* d : {&a, &b}) {
    set_joint_targets(model, *d, q);
    run(model, *d, 300);
  }
  EXPECT_EQ(std::memcmp(a.mj->qpos, b.mj->qpos, sizeof(mjtNum) * static_cast<size_t>(nq)), 0);
  ExpectNoWarnings(a.mj.get());
  ExpectNoWarnings(b.mj.get());
}

TEST_F(DataTest, HumanSweepingThroughTheRobotMakesContactsAndStaysStable) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data data = make_data(model);
  int contacts = 0;
  double fastest = 0;
  // Arms raised forward, the person turns so the arms sweep through the robot's wrist.
  for (int i = 0; i < 1500; ++i) {
    const double s = std::min(1.0, i / 600.0);
    human::SkeletonPose pose =
        human::SkeletonPose::Standing(model.skeleton, 1.0, 0.0, core::kPi - 0.7 + 1.4 * s);
    for (const auto side : {human::Side::kLeft, human::Side::kRight})
      pose.local[static_cast<size_t>(human::index(human::shoulder(side)))] =
          core::axis_angle(Vec3::UnitY(), -1.35);
    set_human_pose(model, data, pose);
    step(model, data);
    for (int c = 0; c < data.mj->ncon; ++c) {
      const auto& t1 = model.geom_tags[static_cast<size_t>(data.mj->contact[c].geom1)];
      const auto& t2 = model.geom_tags[static_cast<size_t>(data.mj->contact[c].geom2)];
      if ((t1.is_robot() && t2.is_human()) || (t2.is_robot() && t1.is_human())) ++contacts;
    }
    for (const double v : arm_joint_velocities(model, data)) fastest = std::max(fastest, std::abs(v));
  }
  EXPECT_GT(contacts, 0);
  EXPECT_TRUE(std::isfinite(fastest));
  EXPECT_LT(fastest, 20.0);
  // The person steps back; pushed aside, the servos bring the arm back home.
  set_human_pose(model, data, model.human_start);
  for (int i = 0; i < 1000; ++i) step(model, data);
  const ArmVector q = arm_joint_positions(model, data);
  for (size_t i = 0; i < model.robot.dof(); ++i) EXPECT_NEAR(q[i], model.robot.joints[i].home, 0.05) << i;
  ExpectNoWarnings(data.mj.get());
}

TEST_F(DataTest, WarningsAreCountedAndDescribed) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data data = make_data(model);
  // A NaN control is a MuJoCo BADCTRL warning (the fixture would fail on the printed warning,
  // so silence the handler for this deliberate one).
  void (*previous)(const char*) = mju_user_warning;
  mju_user_warning = [](const char*) {};
  data.mj->ctrl[0] = std::nan("");
  mj_step(model.m(), data.mj.get());
  mju_user_warning = previous;
  EXPECT_EQ(warning_count(data), 1);
  EXPECT_EQ(warning_summary(data).rfind("BADCTRL x1", 0), 0u) << warning_summary(data);
  reset(model, data);
  EXPECT_EQ(warning_count(data), 0);
}

}  // namespace
}  // namespace hribench::sim
