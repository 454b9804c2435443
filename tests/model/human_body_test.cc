// The human body in the model: mocap bodies at the skeleton's joint frames, capsules as in
// human::body_capsules, palm sites in the human layer's hand convention.

#include <cmath>

#include <gtest/gtest.h>

#include "human/arm_ik.h"
#include "model/model.h"
#include "support/mujoco_fixture.h"

namespace hribench::model {
namespace {

using HumanBodyTest = testing::MujocoTest;
using core::Vec3;

TEST_F(HumanBodyTest, MocapBodiesSitAtTheJointFramesOfTheStartPose) {
  SceneSpec spec = SceneSpec::Default();
  spec.human.height = 1.6;
  spec.human.x = 1.3;
  spec.human.y = 0.2;
  const Model model = build(spec);
  const mjModel* m = model.m();
  mjData* d = mj_makeData(m);
  mj_resetDataKeyframe(m, d, 0);
  mj_kinematics(m, d);
  EXPECT_NEAR(model.skeleton.height, 1.6, 1e-12);
  const auto X = human::forward_kinematics(model.skeleton, model.human_start);
  for (size_t j = 0; j < human::kNumJoints; ++j) {
    const int b = model.human_body[j];
    const Vec3 p(d->xpos[3 * b], d->xpos[3 * b + 1], d->xpos[3 * b + 2]);
    EXPECT_LT((p - X[j].translation).norm(), 1e-7) << j;  // MJCF numbers have 9 digits
  }
  // Feet on the floor: the lowest capsule point is near z = 0.
  double lowest = 1e9;
  for (size_t c = 0; c < model.human_capsules.size(); ++c) {
    const int g = model.human_capsule_geom[c];
    EXPECT_EQ(m->geom_type[g], mjGEOM_CAPSULE);
    EXPECT_NEAR(m->geom_size[3 * g], model.human_capsules[c].radius, 1e-9);
    // Capsule end points: centre +- half-length along the geom's z axis.
    const double axis_z = d->geom_xmat[9 * g + 8];
    lowest = std::min(lowest, d->geom_xpos[3 * g + 2] - std::abs(axis_z) * m->geom_size[3 * g + 1] -
                                  m->geom_size[3 * g]);
  }
  EXPECT_NEAR(lowest, 0.0, 0.03);
  ExpectNoWarnings(d);
  mj_deleteData(d);
}

TEST_F(HumanBodyTest, PalmFramesFollowTheHumanHandConvention) {
  const Model model = build(SceneSpec::Default());
  const auto X = human::forward_kinematics(model.skeleton, model.human_start);
  for (const human::Side side : {human::Side::kLeft, human::Side::kRight}) {
    const core::Pose& X_W_wrist = X[static_cast<size_t>(human::index(human::wrist(side)))];
    const core::Pose X_W_palm = X_W_wrist * model.X_wrist_palm[static_cast<size_t>(side)];
    EXPECT_LT((X_W_palm.translation - human::palm_centre(model.skeleton, X_W_wrist)).norm(), 1e-9);
    EXPECT_LT((X_W_palm.rotation * Vec3::UnitZ() - human::palm_normal(side, X_W_wrist)).norm(), 1e-9);
    const int site = mj_name2id(model.m(), mjOBJ_SITE,
                                side == human::Side::kLeft ? "palm_left" : "palm_right");
    EXPECT_GE(site, 0);
  }
}

TEST_F(HumanBodyTest, HeldObjectStartsOffThePalmWithTheForearmForward) {
  SceneSpec spec;
  ObjectSpec cup;
  cup.kind = "cup";
  cup.held_by = human::Side::kLeft;
  spec.objects.push_back(cup);
  const Model model = build(spec);
  const auto X = human::forward_kinematics(model.skeleton, model.human_start);
  const core::Pose& wrist = X[static_cast<size_t>(human::index(human::Joint::kLeftWrist))];
  const core::Pose& elbow = X[static_cast<size_t>(human::index(human::Joint::kLeftElbow))];
  // Forearm horizontal, pointing where the person faces (-x: toward the robot).
  const Vec3 forearm = (wrist.translation - elbow.translation).normalized();
  EXPECT_NEAR(forearm.x(), -1.0, 1e-6);
  // The cup is upright, beside the palm on the palm side, not overlapping the hand capsule.
  const ObjectInfo& o = model.objects[0];
  EXPECT_LT(Eigen::AngleAxisd(o.X_W_start.rotation *
                              core::axis_angle(Vec3::UnitZ(), spec.human.yaw).conjugate())
                .angle(),
            1e-9);
  const Vec3 centre = o.X_W_start * Vec3(0, 0, o.half_extents.z());
  const Vec3 palm = human::palm_centre(model.skeleton, wrist);
  const Vec3 normal = human::palm_normal(human::Side::kLeft, wrist);
  EXPECT_GT((centre - palm).dot(normal), 0.035 + o.half_extents.y());
  EXPECT_LT((centre - palm).norm(), 0.12);
}

// The drawn hands (human/hand.h, render/renderer.h): the model does not draw the hands' contact
// capsules (group 3); it carries the person's height and room in mjData::userdata for the hands'
// shapes, from which the renderers draw the fingers.
TEST_F(HumanBodyTest, HandCapsulesAreNotDrawnAndTheHandsCanBe) {
  SceneSpec spec = SceneSpec::Default();
  spec.human.height = 1.62;
  const Model model = build(spec);
  const mjModel* m = model.m();
  int hands = 0;
  for (size_t c = 0; c < model.human_capsules.size(); ++c) {
    const int g = model.human_capsule_geom[c];
    const bool hand = model.human_capsules[c].region == human::BodyRegion::kHand;
    hands += hand ? 1 : 0;
    EXPECT_EQ(m->geom_group[g], hand ? 3 : 0) << model.human_capsules[c].name;
  }
  EXPECT_EQ(hands, 2);
  EXPECT_EQ(m->nuserdata, kHandShapeValues);
  const int height = mj_name2id(m, mjOBJ_NUMERIC, kHumanHeightNumeric);
  ASSERT_GE(height, 0);
  EXPECT_DOUBLE_EQ(m->numeric_data[m->numeric_adr[height]], 1.62);
  // Without a person there is nothing to draw.
  SceneSpec empty = SceneSpec::Default();
  empty.human.present = false;
  EXPECT_LT(mj_name2id(build(empty).m(), mjOBJ_NUMERIC, kHumanHeightNumeric), 0);
}

}  // namespace
}  // namespace hribench::model
