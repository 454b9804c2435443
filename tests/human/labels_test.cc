#include "human/labels.h"

#include <gtest/gtest.h>

#include <cmath>

#include "human/arm_ik.h"

namespace hribench::human {
namespace {

using core::Vec3;

Clip still_clip(const Skeleton& k, const SkeletonPose& pose, size_t frames) {
  Clip c;
  c.skeleton = k;
  c.fps = 10;
  c.frames.assign(frames, pose);
  c.phases = {{"hold", 0.0, static_cast<double>(frames - 1) / 10}};
  return c;
}

TEST(LabelsTest, SegmentDistanceCoversTheCases) {
  // Crossing segments at right angles, 1 apart.
  EXPECT_NEAR(segment_distance(Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, 1), Vec3(0, 1, 1)), 1, 1e-12);
  // Parallel, overlapping.
  EXPECT_NEAR(segment_distance(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 0.5, 0), Vec3(3, 0.5, 0)), 0.5, 1e-12);
  // End point to end point.
  EXPECT_NEAR(segment_distance(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 1, 0)), 1, 1e-12);
  // Degenerate segments (points).
  EXPECT_NEAR(segment_distance(Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 3, 4), Vec3(0, 3, 4)), 5, 1e-12);
  EXPECT_NEAR(segment_distance(Vec3(0, 1, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(1, 0, 0)), 1, 1e-12);
  // Intersecting.
  EXPECT_NEAR(segment_distance(Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 1, 0)), 0, 1e-12);
}

TEST(LabelsTest, HandPointsAreNamed) {
  EXPECT_EQ(hand_point_from_name("palm"), HandPoint::kPalm);
  EXPECT_EQ(hand_point_from_name("hand"), HandPoint::kPalm);
  EXPECT_EQ(hand_point_from_name("wrist"), HandPoint::kWrist);
  EXPECT_EQ(hand_point_from_name("index"), HandPoint::kIndexTip);
  EXPECT_FALSE(hand_point_from_name("thumb").has_value());
  const Skeleton k = Skeleton::FromHeight(1.75);
  const SkeletonPose rest = SkeletonPose::Standing(k, 0, 0, 0);
  const Vec3 w = hand_point(k, rest, Side::kLeft, HandPoint::kWrist);
  EXPECT_NEAR(w.z() - hand_point(k, rest, Side::kLeft, HandPoint::kPalm).z(), k.palm_distance, 1e-12);
  EXPECT_NEAR(w.z() - hand_point(k, rest, Side::kLeft, HandPoint::kIndexTip).z(), k.hand_length, 1e-12);
}

TEST(LabelsTest, RestPoseIsClean) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  const Clip c = still_clip(k, SkeletonPose::Standing(k, 1, 2, 0.5), 5);
  EXPECT_TRUE(check_self_penetration(c).ok) << check_self_penetration(c).message;
  EXPECT_TRUE(check_clip_joint_limits(c).ok);
  EXPECT_TRUE(check_bone_lengths(c).ok);
  const CheckResult stable = check_stable_in_zone(
      c, Side::kRight, HandPoint::kWrist,
      {hand_point(k, c.frames[0], Side::kRight, HandPoint::kWrist), 0.01}, "hold");
  EXPECT_TRUE(stable.ok);
  EXPECT_EQ(stable.worst, 0);
}

TEST(LabelsTest, SelfPenetrationIsFoundAndNamed) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  SkeletonPose pose = SkeletonPose::Standing(k, 0, 0, 0);
  // The left upper arm swung across the chest: the forearm goes through the torso.
  solve_arm(k, pose, Side::kLeft,
            {forward_kinematics(k, pose)[index(Joint::kRightShoulder)].translation + Vec3(0.0, 0.05, -0.15), 0, std::nullopt});
  const CheckResult r = check_self_penetration(still_clip(k, pose, 3));
  EXPECT_FALSE(r.ok);
  EXPECT_GT(r.worst, 0.02);
  EXPECT_NE(r.message.find("left_forearm"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("self-penetration"), std::string::npos);
}

TEST(LabelsTest, JointLimitAndBoneLengthFailuresAreReported) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  SkeletonPose bad = SkeletonPose::Standing(k, 0, 0, 0);
  bad.local[index(Joint::kRightKnee)] = core::axis_angle(Vec3::UnitY(), -0.8);
  Clip c = still_clip(k, SkeletonPose::Standing(k, 0, 0, 0), 4);
  c.frames[2] = bad;
  const CheckResult limits = check_clip_joint_limits(c);
  EXPECT_FALSE(limits.ok);
  EXPECT_NEAR(limits.time, 0.2, 1e-12);
  EXPECT_NEAR(limits.worst, 0.8 * 180 / core::kPi - 10, 1e-6);
  EXPECT_EQ(limits.message, "knee hyperextension of right_knee is 45.8 deg (limit 10) at t=0.20 s");
  // Forward kinematics normalises rotations, so lengths only break with non-finite values
  // (a broken importer).
  EXPECT_TRUE(check_bone_lengths(c).ok);
  SkeletonPose broken = SkeletonPose::Standing(k, 0, 0, 0);
  broken.local[index(Joint::kLeftElbow)] = core::Quat(std::nan(""), 0, 0, 0);
  c.frames[1] = broken;
  const CheckResult bones = check_bone_lengths(c);
  EXPECT_FALSE(bones.ok);
  EXPECT_NE(bones.message.find("left_wrist"), std::string::npos) << bones.message;
  EXPECT_NEAR(bones.time, 0.1, 1e-12);
  const CheckResult nan_limits = check_clip_joint_limits(c);
  EXPECT_FALSE(nan_limits.ok);
  EXPECT_EQ(nan_limits.message.rfind("non-finite rotation of left_elbow", 0), 0u) << nan_limits.message;
}

TEST(LabelsTest, PointingAndZoneChecksNameThePhaseAndTheMiss) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  SkeletonPose pose = SkeletonPose::Standing(k, 0, 0, 0);
  const Vec3 S = forward_kinematics(k, pose)[index(Joint::kRightShoulder)].translation;
  const Vec3 target = S + Vec3(1.0, 0, -0.5);
  const Vec3 dir = (target - S).normalized();
  solve_arm(k, pose, Side::kRight, {S + 0.4 * dir, 0.3, hand_rotation(Side::kRight, dir, -Vec3::UnitZ())});
  const Clip c = still_clip(k, pose, 3);
  EXPECT_LT(pointing_ray_distance(k, pose, Side::kRight, target), 1e-9);
  EXPECT_TRUE(check_pointing(c, Side::kRight, target, 0.01).ok);
  const CheckResult miss = check_pointing(c, Side::kRight, target + Vec3(0, 0.2, 0), 0.05);
  EXPECT_FALSE(miss.ok);
  EXPECT_NEAR(miss.worst, 0.2, 0.01);
  EXPECT_NE(miss.message.find("hold: the pointing ray misses the target by"), std::string::npos);
  // A target behind the shoulder is measured to the shoulder.
  EXPECT_NEAR(pointing_ray_distance(k, pose, Side::kRight, S - 0.3 * dir), 0.3, 1e-9);
  const CheckResult none = check_pointing(c, Side::kRight, target, 0.01, "stroke");
  EXPECT_FALSE(none.ok);
  EXPECT_EQ(none.message, "the clip has no frames in a phase 'stroke'");
  const Zone far{S + Vec3(0, 0, 1), 0.05};
  const CheckResult out = check_stable_in_zone(c, Side::kRight, HandPoint::kPalm, far, "hold");
  EXPECT_FALSE(out.ok);
  EXPECT_NE(out.message.find("hold: the hand leaves the zone by"), std::string::npos);
}

TEST(LabelsTest, EnteringABoxNeedsToStartOutside) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  const SkeletonPose rest = SkeletonPose::Standing(k, 0, 0, 0);
  const Vec3 p = hand_point(k, rest, Side::kLeft, HandPoint::kPalm);
  const Box around{p - Vec3(0.1, 0.1, 0.1), p + Vec3(0.1, 0.1, 0.1)};
  EXPECT_TRUE(around.contains(p));
  EXPECT_FALSE(around.contains(p + Vec3(0, 0, 0.2)));
  const CheckResult r = check_enters_box(still_clip(k, rest, 3), Side::kLeft, HandPoint::kPalm, around);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.message, "the hand is inside the workspace already at the start");
}

}  // namespace
}  // namespace hribench::human
