#include "sim/separation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include "core/rng.h"
#include "sim/data.h"
#include "support/default_scene.h"
#include "support/mujoco_fixture.h"

namespace hribench::sim {
namespace {

using core::Vec3;
using model::GeomOwner;
using model::GeomTag;

// A small hand-made world whose geometry is known exactly: a robot "link" (a box on a hinge)
// with a capsule arm, a robot "finger" cylinder, a visual-only robot sphere, a floor plane,
// and two mocap human capsules (a hand and a forearm).
constexpr char kSceneXml[] = R"(
<mujoco>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <body name="link" pos="0 0 0.5">
      <joint name="hinge" type="hinge" axis="0 0 1"/>
      <geom name="r_box" type="box" size="0.1 0.05 0.2"/>
      <geom name="r_arm" type="capsule" fromto="0 0 0.3 0 0 0.6" size="0.04"/>
      <geom name="r_visual" type="sphere" pos="0 -0.3 0" size="0.05" contype="0" conaffinity="0"/>
    </body>
    <body name="wrist" pos="-0.5 0 0.5">
      <geom name="r_ell" type="ellipsoid" size="0.1 0.05 0.03"/>
    </body>
    <body name="finger" pos="0.5 0 0.5">
      <geom name="r_cyl" type="cylinder" size="0.05 0.1"/>
    </body>
    <body name="h_hand" mocap="true" pos="3 0 0.5">
      <geom name="h_hand" type="capsule" fromto="0 0 0 0 0 -0.2" size="0.035" contype="0" conaffinity="0" group="1"/>
      <geom name="h_hand_pad" type="capsule" fromto="0 0 0 0 0 -0.2" size="0.035" contype="8" conaffinity="2"/>
    </body>
    <body name="h_forearm" mocap="true" pos="-3 0 0.5">
      <geom name="h_forearm" type="capsule" fromto="0 0 0 0.2 0 0" size="0.04" contype="8" conaffinity="2"/>
    </body>
  </worldbody>
</mujoco>)";

struct Scene {
  model::Model model;
  std::unique_ptr<mjData, void (*)(mjData*)> data{nullptr, mj_deleteData};
  int hand_mocap = -1;
  int forearm_mocap = -1;

  int geom(const char* name) const { return mj_name2id(model.m(), mjOBJ_GEOM, name); }
  mjData& d() { return *data; }

  // Moves a mocap body and recomputes positions; fails the test on any MuJoCo warning.
  void Place(int mocap, const Vec3& pos, const core::Quat& rot = core::Quat::Identity()) {
    for (int i = 0; i < 3; ++i) data->mocap_pos[3 * mocap + i] = pos[i];
    core::quat_to_wxyz(rot, data->mocap_quat + 4 * mocap);
    mj_forward(model.m(), data.get());
    for (int w = 0; w < mjNWARNING; ++w) {
      EXPECT_EQ(data->warning[w].number, 0) << "MuJoCo warning " << w;
    }
  }
};

std::unique_ptr<Scene> LoadScene() {
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const int size = static_cast<int>(std::strlen(kSceneXml));
  EXPECT_EQ(mj_makeEmptyFileVFS(vfs.get(), "scene.xml", size), 0);
  std::memcpy(vfs->filedata[0], kSceneXml, static_cast<size_t>(size));
  char error[1000] = "";
  mjModel* m = mj_loadXML("scene.xml", vfs.get(), error, sizeof(error));
  mj_deleteVFS(vfs.get());
  EXPECT_NE(m, nullptr) << error;
  auto scene = std::make_unique<Scene>();
  scene->model.mj.reset(m);
  scene->model.geom_tags.resize(static_cast<size_t>(m->ngeom));
  const auto tag = [&](const char* name, GeomTag t) {
    scene->model.geom_tags[static_cast<size_t>(scene->geom(name))] = t;
  };
  tag("floor", {GeomOwner::kFloor, -1, human::BodyRegion::kTorso, human::Joint::kPelvis});
  tag("r_box", {GeomOwner::kRobotLink, 3, human::BodyRegion::kTorso, human::Joint::kPelvis});
  tag("r_arm", {GeomOwner::kRobotLink, 3, human::BodyRegion::kTorso, human::Joint::kPelvis});
  tag("r_visual", {GeomOwner::kRobotLink, 3, human::BodyRegion::kTorso, human::Joint::kPelvis});
  tag("r_ell", {GeomOwner::kRobotLink, 6, human::BodyRegion::kTorso, human::Joint::kPelvis});
  tag("r_cyl", {GeomOwner::kRobotFinger, 0, human::BodyRegion::kTorso, human::Joint::kPelvis});
  tag("h_hand", {GeomOwner::kHuman, 0, human::BodyRegion::kHand, human::Joint::kRightWrist});
  tag("h_hand_pad", {GeomOwner::kHuman, 0, human::BodyRegion::kHand, human::Joint::kRightWrist});
  tag("h_forearm",
      {GeomOwner::kHuman, 1, human::BodyRegion::kForearm, human::Joint::kRightElbow});
  scene->data.reset(mj_makeData(m));
  scene->hand_mocap = m->body_mocapid[mj_name2id(m, mjOBJ_BODY, "h_hand")];
  scene->forearm_mocap = m->body_mocapid[mj_name2id(m, mjOBJ_BODY, "h_forearm")];
  mj_forward(m, scene->data.get());
  return scene;
}

// Every test fails on any MuJoCo warning (the loader's and mj_forward's, via the fixture; the
// mjData counters are checked in Scene::Place).
class SeparationMonitorTest : public testing::MujocoTest {};
class MinSeparation : public testing::MujocoTest {};

TEST_F(SeparationMonitorTest, ListsCollidingRobotAndHumanGeomsOnly) {
  auto s = LoadScene();
  const SeparationMonitor monitor = SeparationMonitor::FromModel(s->model);
  // Box, arm capsule, ellipsoid (as its enclosing sphere), finger cylinder; not the visual.
  ASSERT_EQ(monitor.robot.size(), 4u);
  EXPECT_EQ(monitor.robot[0].id, s->geom("r_box"));
  EXPECT_EQ(monitor.robot[0].type, ShapeType::kBox);
  EXPECT_EQ(monitor.robot[1].type, ShapeType::kCapsule);
  EXPECT_EQ(monitor.robot[2].type, ShapeType::kSphere);
  EXPECT_DOUBLE_EQ(monitor.robot[2].size[0], 0.1);
  EXPECT_EQ(monitor.robot[3].type, ShapeType::kCylinder);
  ASSERT_EQ(monitor.human.size(), 2u);  // the hand pad and the forearm; not the visual hand
  EXPECT_EQ(monitor.human[0].id, s->geom("h_hand_pad"));
  EXPECT_EQ(monitor.human[0].region, human::BodyRegion::kHand);
  EXPECT_EQ(monitor.human[1].region, human::BodyRegion::kForearm);
}

TEST_F(MinSeparation, MatchesHandComputedDistances) {
  auto s = LoadScene();
  const SeparationMonitor monitor = SeparationMonitor::FromModel(s->model);
  // Box: x in [-0.1, 0.1], y in [-0.05, 0.05], z in [0.3, 0.7]. Arm capsule: axis x = y = 0,
  // z in [0.8, 1.1], r 0.04. Cylinder: axis along z at x = 0.5, r 0.05, z in [0.4, 0.6].
  // Hand: vertical segment from the mocap position down 0.2, r 0.035.

  // Beside the cylinder: 0.45 - 0.3 - 0.035 (the box is 0.2 - 0.035 away).
  s->Place(s->hand_mocap, Vec3(0.3, 0, 0.6));
  Separation sep = min_separation(monitor, s->d());
  EXPECT_NEAR(sep.distance, 0.115, 1e-9);
  EXPECT_EQ(sep.robot_geom, s->geom("r_cyl"));
  EXPECT_EQ(sep.human_geom, s->geom("h_hand_pad"));
  EXPECT_EQ(sep.region, human::BodyRegion::kHand);
  EXPECT_NEAR((sep.point_robot_W - Vec3(0.45, 0, sep.point_robot_W.z())).norm(), 0, 1e-9);
  EXPECT_NEAR(sep.point_human_W.x(), 0.335, 1e-9);

  // Beside the arm capsule, level with it: 0.3 - 0.04 - 0.035 (the box corner is farther).
  s->Place(s->hand_mocap, Vec3(-0.3, 0, 1.1));
  sep = min_separation(monitor, s->d());
  EXPECT_NEAR(sep.distance, 0.3 - 0.04 - 0.035, 1e-9);
  EXPECT_EQ(sep.robot_geom, s->geom("r_arm"));

  // Beyond the ellipsoid's long (x) axis: its enclosing sphere is exact in that direction.
  s->Place(s->hand_mocap, Vec3(-0.8, 0, 0.6));
  sep = min_separation(monitor, s->d());
  EXPECT_NEAR(sep.distance, 0.3 - 0.1 - 0.035, 1e-9);
  EXPECT_EQ(sep.robot_geom, s->geom("r_ell"));

  // Penetrating the box's +x face by 1.5 cm.
  s->Place(s->hand_mocap, Vec3(0.12, 0, 0.6));
  sep = min_separation(monitor, s->d());
  EXPECT_NEAR(sep.distance, 0.02 - 0.035, 1e-9);
  EXPECT_EQ(sep.robot_geom, s->geom("r_box"));

  // The hand far away, the forearm (horizontal, along x) beside the box's +y face.
  s->Place(s->hand_mocap, Vec3(3, 3, 3));
  s->Place(s->forearm_mocap, Vec3(-0.1, 0.2, 0.5));
  sep = min_separation(monitor, s->d());
  EXPECT_NEAR(sep.distance, 0.15 - 0.04, 1e-9);
  EXPECT_EQ(sep.human_geom, s->geom("h_forearm"));
  EXPECT_EQ(sep.region, human::BodyRegion::kForearm);
  EXPECT_NEAR((sep.point_human_W - sep.point_robot_W).norm(), sep.distance, 1e-9);

  // Rotating the forearm capsule 90 degrees about z points it along +y, away from the box:
  // its near end is still 0.15 from the face, now with its hemispherical cap.
  s->Place(s->forearm_mocap, Vec3(0.0, 0.2, 0.5), core::axis_angle(Vec3::UnitZ(), core::kPi / 2));
  EXPECT_NEAR(min_separation(monitor, s->d()).distance, 0.15 - 0.04, 1e-9);

  // Turning the robot's hinge by 90 degrees swaps the box's x and y extents.
  s->d().qpos[0] = core::kPi / 2;
  s->Place(s->forearm_mocap, Vec3(-3, 0, 0.5));
  s->Place(s->hand_mocap, Vec3(0.3, 0.0, 0.9));  // hand z in [0.7, 0.9], above the box top
  sep = min_separation(monitor, s->d());
  // Box now spans x in [-0.05, 0.05]: its top edge at x = 0.05, z = 0.7 is 0.25 away; the arm
  // capsule is 0.3 - 0.04 away; the cylinder's rim at (0.45, 0.6) is hypot(0.15, 0.1) away.
  EXPECT_NEAR(sep.distance, std::hypot(0.15, 0.1) - 0.035, 1e-9);
  EXPECT_EQ(sep.robot_geom, s->geom("r_cyl"));
}

TEST_F(MinSeparation, RobotPointMotionIsTheClosestPointsVelocityTowardTheHuman) {
  auto s = LoadScene();
  const SeparationMonitor monitor = SeparationMonitor::FromModel(s->model);
  // The hand beside the box's (+x, +y) vertical edge at (0.1, 0.05): direction (1, 1)/sqrt 2.
  s->d().qvel[0] = 2.0;  // hinge about z: the edge moves at 2 * (-0.05, 0.1, 0) m/s
  s->Place(s->hand_mocap, Vec3(0.2, 0.15, 0.6));
  const Separation sep = min_separation(monitor, s->d());
  ASSERT_EQ(sep.robot_geom, s->geom("r_box"));
  EXPECT_NEAR(sep.distance, std::sqrt(0.02) - 0.035, 1e-9);
  const RobotPointMotion motion = robot_point_motion(*s->model.m(), s->d(), sep);
  EXPECT_NEAR((motion.velocity_W - Vec3(-0.1, 0.2, 0)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(motion.speed_toward_human, (-0.1 + 0.2) / std::sqrt(2.0), 1e-9);
  // Turning the other way moves the edge away from the hand.
  s->d().qvel[0] = -2.0;
  mj_forward(s->model.m(), &s->d());
  EXPECT_NEAR(robot_point_motion(*s->model.m(), s->d(), min_separation(monitor, s->d()))
                  .speed_toward_human,
              -(-0.1 + 0.2) / std::sqrt(2.0), 1e-9);
  // No robot or human: no motion.
  EXPECT_EQ(robot_point_motion(*s->model.m(), s->d(), Separation{}).speed_toward_human, 0.0);
}

TEST_F(MinSeparation, EqualsTheMinimumOverAllPairsOnRandomPlacements) {
  auto s = LoadScene();
  const SeparationMonitor monitor = SeparationMonitor::FromModel(s->model);
  core::Rng rng(3);
  const auto random_quat = [&] {
    return core::Quat(rng.normal(0, 1), rng.normal(0, 1), rng.normal(0, 1), rng.normal(0, 1))
        .normalized();
  };
  for (int trial = 0; trial < 200; ++trial) {
    s->d().qpos[0] = rng.uniform(-3, 3);
    s->Place(s->hand_mocap,
             Vec3(rng.uniform(-0.8, 0.8), rng.uniform(-0.8, 0.8), rng.uniform(0, 1.4)),
             random_quat());
    s->Place(s->forearm_mocap,
             Vec3(rng.uniform(-0.8, 0.8), rng.uniform(-0.8, 0.8), rng.uniform(0, 1.4)),
             random_quat());
    const Separation sep = min_separation(monitor, s->d());
    double brute = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < monitor.robot.size(); ++i) {
      for (size_t j = 0; j < monitor.human.size(); ++j) {
        brute = std::min(brute, pair_separation(monitor, s->d(), i, j).distance);
      }
    }
    ASSERT_TRUE(sep.valid());
    EXPECT_EQ(sep.distance, brute) << "trial " << trial;
    // The one-off form agrees with the monitor form.
    EXPECT_EQ(min_separation(s->model, s->d()).distance, sep.distance);
  }
}

TEST_F(MinSeparation, InfiniteWithoutHumanGeoms) {
  auto s = LoadScene();
  for (GeomTag& tag : s->model.geom_tags) {
    if (tag.is_human()) tag.owner = GeomOwner::kOther;
  }
  const Separation sep = min_separation(s->model, s->d());
  EXPECT_FALSE(sep.valid());
  EXPECT_TRUE(std::isinf(sep.distance));
}

// The real scene (model::build) with the human posed through sim::set_human_pose.
using SceneSeparation = testing::DefaultScene;

TEST_F(SceneSeparation, HandTipBesideTheBaseCylinderIsAtTheHandComputedDistance) {
  // The robot base (link 0) cylinder, read from the model: axis vertical, radius r_base.
  int base = -1;
  for (int g = 0; g < model_.m()->ngeom; ++g) {
    const GeomTag& tag = model_.geom_tags[static_cast<size_t>(g)];
    if (tag.owner == GeomOwner::kRobotLink && tag.index == 0 &&
        model_.m()->geom_type[g] == mjGEOM_CYLINDER) {
      base = g;
    }
  }
  ASSERT_GE(base, 0);
  const mjData& d = *data_.mj;
  const auto b = static_cast<size_t>(base);
  const Vec3 centre(d.geom_xpos[3 * b], d.geom_xpos[3 * b + 1], d.geom_xpos[3 * b + 2]);
  ASSERT_NEAR(std::abs(d.geom_xmat[9 * b + 8]), 1.0, 1e-12);  // axis along world z
  const double r_base = model_.m()->geom_size[3 * b];

  // The right arm raised straight forward, the person facing -x (toward the robot): the hand
  // capsule lies along -x. Put its tip (the segment's far end) `gap` + radii from the axis.
  human::SkeletonPose pose = human::SkeletonPose::Standing(model_.skeleton, 0, 0, core::kPi);
  pose.local[static_cast<size_t>(human::index(human::Joint::kRightShoulder))] =
      core::axis_angle(Vec3::UnitY(), -core::kPi / 2);
  const human::BodyCapsule* hand = nullptr;
  for (const human::BodyCapsule& c : model_.human_capsules) {
    if (c.name == "right_hand") hand = &c;
  }
  ASSERT_NE(hand, nullptr);
  const auto X_WJ = human::forward_kinematics(model_.skeleton, pose);
  const Vec3 tip = X_WJ[static_cast<size_t>(human::index(hand->joint))] * hand->to;
  for (const double gap : {0.10, 0.16}) {
    const Vec3 want_tip = centre + Vec3(r_base + hand->radius + gap, 0, 0);
    human::SkeletonPose placed = pose;
    placed.X_WP.translation += want_tip - tip;
    set_human_pose(model_, data_, placed);
    forward(model_, data_);
    const Separation sep = min_separation(model_, data_);
    EXPECT_NEAR(sep.distance, gap, 1e-9);
    EXPECT_EQ(sep.robot_geom, base);
    EXPECT_EQ(sep.region, human::BodyRegion::kHand);
    EXPECT_NEAR((sep.point_robot_W - (centre + Vec3(r_base, 0, 0))).norm(), 0.0, 1e-9);
  }
}

TEST_F(SceneSeparation, MovingTheHumanAlongTheSeparationNormalAddsExactlyThatDistance) {
  // The default scene: the human stands at the far table edge facing the robot at home.
  const SeparationMonitor monitor = SeparationMonitor::FromModel(model_);
  const Separation before = min_separation(monitor, data_);
  ASSERT_TRUE(before.valid());
  EXPECT_GT(before.distance, 0.3);
  EXPECT_LT(before.distance, 1.2);
  const Vec3 n = (before.point_human_W - before.point_robot_W).normalized();
  human::SkeletonPose moved = model_.human_start;
  moved.X_WP.translation += 0.05 * n;
  set_human_pose(model_, data_, moved);
  forward(model_, data_);
  const Separation after = min_separation(monitor, data_);
  EXPECT_NEAR(after.distance, before.distance + 0.05, 1e-9);
  EXPECT_EQ(after.robot_geom, before.robot_geom);
  EXPECT_EQ(after.human_geom, before.human_geom);
}

}  // namespace
}  // namespace hribench::sim
