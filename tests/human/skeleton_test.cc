#include "human/skeleton.h"

#include <gtest/gtest.h>

#include "core/errors.h"

namespace hribench::human {
namespace {

TEST(SkeletonTest, NamesAndParentsFollowSmpl) {
  EXPECT_EQ(joint_name(Joint::kPelvis), "pelvis");
  EXPECT_EQ(joint_name(Joint::kRightWrist), "right_wrist");
  EXPECT_EQ(joint_from_name("left_elbow"), Joint::kLeftElbow);
  EXPECT_FALSE(joint_from_name("tail").has_value());
  EXPECT_FALSE(parent(Joint::kPelvis).has_value());
  EXPECT_EQ(parent(Joint::kHead), Joint::kNeck);
  EXPECT_EQ(parent(Joint::kLeftShoulder), Joint::kLeftCollar);
  for (int j = 1; j < kNumJoints; ++j) EXPECT_LT(index(*parent(static_cast<Joint>(j))), j);
}

TEST(SkeletonTest, RestPoseStandsOnTheFloorAtTheRequestedHeight) {
  for (const double height : {1.55, 1.75, 1.95}) {
    const Skeleton k = Skeleton::FromHeight(height);
    const auto X = forward_kinematics(k, SkeletonPose::Standing(k, 0, 0, 0));
    // Soles on the floor: ankle joints at the ankle height above z = 0.
    EXPECT_NEAR(X[index(Joint::kLeftAnkle)].translation.z(), 0.06 * k.scale, 1e-9);
    // Crown at the standing height.
    EXPECT_NEAR(X[index(Joint::kNeck)].translation.z() + k.crown_above_neck, height, 1e-9);
    // Arms hang down: wrist below elbow below shoulder.
    EXPECT_LT(X[index(Joint::kLeftWrist)].translation.z(), X[index(Joint::kLeftElbow)].translation.z());
    EXPECT_GT(X[index(Joint::kLeftWrist)].translation.y(), 0.1);  // left is +y
  }
}

TEST(SkeletonTest, BoneLengthsScaleWithHeight) {
  const Skeleton a = Skeleton::FromHeight(1.70);
  const Skeleton b = Skeleton::FromHeight(1.70 * 1.1);
  EXPECT_NEAR(a.bone_length(Joint::kLeftElbow) / a.scale, 0.260, 1e-12);  // upper arm, HumanML3D
  for (int j = 1; j < kNumJoints; ++j) {
    EXPECT_NEAR(b.bone_length(static_cast<Joint>(j)), 1.1 * a.bone_length(static_cast<Joint>(j)), 1e-12);
  }
}

TEST(SkeletonTest, ForwardKinematicsPreservesBoneLengthsUnderRotation) {
  const Skeleton k = Skeleton::FromHeight(1.8);
  SkeletonPose pose = SkeletonPose::Standing(k, 1.5, 0.2, core::kPi);
  pose.local[index(Joint::kRightShoulder)] = core::axis_angle(core::Vec3(0.3, 1, 0.2), 1.1);
  pose.local[index(Joint::kRightElbow)] = core::axis_angle(core::Vec3::UnitY(), -1.2);
  pose.local[index(Joint::kSpine2)] = core::axis_angle(core::Vec3::UnitY(), 0.4);
  const auto X = forward_kinematics(k, pose);
  for (int j = 1; j < kNumJoints; ++j) {
    const auto p = static_cast<size_t>(index(*parent(static_cast<Joint>(j))));
    EXPECT_NEAR((X[static_cast<size_t>(j)].translation - X[p].translation).norm(),
                k.bone_length(static_cast<Joint>(j)), 1e-12);
  }
  // Facing -x (yaw pi): the person's left is world -y.
  EXPECT_LT(X[index(Joint::kLeftHip)].translation.y(), 0.2);
}

// joint_pose is forward_kinematics' entry to the bit (the lean's inner loops use it, and
// episodes must not change: docs/performance.md), for every joint of a pose that turns them all.
TEST(SkeletonTest, OneJointsPoseIsForwardKinematicsToTheBit) {
  const Skeleton k = Skeleton::FromHeight(1.63);
  SkeletonPose pose = SkeletonPose::Standing(k, 0.7, -0.4, 2.1);
  for (int j = 1; j < kNumJoints; ++j) {
    pose.local[static_cast<size_t>(j)] =
        core::axis_angle(core::Vec3(0.2 * j, 1 - 0.05 * j, 0.3), 0.07 * j - 0.6);
  }
  const auto X = forward_kinematics(k, pose);
  for (int j = 0; j < kNumJoints; ++j) {
    const core::Pose one = joint_pose(k, pose, static_cast<Joint>(j));
    const core::Pose& all = X[static_cast<size_t>(j)];
    EXPECT_EQ(one.translation, all.translation) << joint_name(static_cast<Joint>(j));
    EXPECT_EQ(one.rotation.coeffs(), all.rotation.coeffs()) << joint_name(static_cast<Joint>(j));
  }
}

TEST(SkeletonTest, RejectsImpossibleHeights) {
  EXPECT_THROW(Skeleton::FromHeight(0.3), core::InputError);
  EXPECT_THROW(Skeleton::FromHeight(std::nan("")), core::InputError);
}

TEST(SkeletonTest, CapsuleBodyCoversEveryRegion) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  const auto capsules = body_capsules(k);
  std::array<int, kNumBodyRegions> per_region{};
  for (const BodyCapsule& c : capsules) {
    EXPECT_GT(c.radius, 0.0);
    ++per_region[static_cast<size_t>(c.region)];
  }
  for (int r = 0; r < kNumBodyRegions; ++r) EXPECT_GT(per_region[static_cast<size_t>(r)], 0) << r;
  EXPECT_EQ(quasi_static_force_limit(BodyRegion::kHand), 140);
  EXPECT_EQ(to_string(BodyRegion::kUpperArm), "upper_arm");
}

TEST(SkeletonTest, InterpolateGoesFromOnePoseToTheOther) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  const SkeletonPose a = SkeletonPose::Standing(k, 0.2, -0.1, 0.3);
  SkeletonPose b = SkeletonPose::Standing(k, 0.4, 0.1, 0.5);
  b.local[static_cast<size_t>(index(Joint::kRightElbow))] = core::axis_angle(core::Vec3::UnitZ(), 1.2);
  b.hands[1].grip = 1;
  const auto same = [](const SkeletonPose& p, const SkeletonPose& q) {
    bool equal = p.X_WP.translation == q.X_WP.translation && p.X_WP.rotation.coeffs() == q.X_WP.rotation.coeffs();
    for (size_t j = 0; j < p.local.size(); ++j) equal = equal && p.local[j].coeffs() == q.local[j].coeffs();
    return equal && p.hands[1].grip == q.hands[1].grip;
  };
  EXPECT_TRUE(same(interpolate(a, b, 0), a));
  EXPECT_TRUE(same(interpolate(a, b, 1), b));
  const SkeletonPose half = interpolate(a, b, 0.5);
  EXPECT_NEAR((half.X_WP.translation - core::Vec3(0.3, 0, a.X_WP.translation.z())).norm(), 0, 1e-12);
  EXPECT_DOUBLE_EQ(half.hands[1].grip, 0.5);
  const double elbow = Eigen::AngleAxisd(half.local[static_cast<size_t>(index(Joint::kRightElbow))]).angle();
  EXPECT_NEAR(elbow, 0.6, 1e-12);  // half the turn
  const double yaw = Eigen::AngleAxisd(half.X_WP.rotation * a.X_WP.rotation.conjugate()).angle();
  EXPECT_NEAR(yaw, 0.1, 1e-12);
}

}  // namespace
}  // namespace hribench::human
