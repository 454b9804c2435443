#include "human/arm_ik.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.h"

namespace hribench::human {
namespace {

using core::Quat;
using core::Vec3;

constexpr double kDeg = core::kPi / 180.0;

Vec3 joint_position(const Skeleton& k, const SkeletonPose& pose, Joint j) {
  return forward_kinematics(k, pose)[static_cast<size_t>(index(j))].translation;
}

TEST(ArmIkTest, WristReachesTargetsInFrontForBothArms) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  const SkeletonPose rest = SkeletonPose::Standing(k, 1.5, 0.1, core::kPi);
  for (const Side side : {Side::kLeft, Side::kRight}) {
    const Vec3 S = joint_position(k, rest, shoulder(side));
    for (double fx : {0.2, 0.3, 0.38}) {
      for (double dz : {-0.3, 0.0, 0.2}) {
        for (double swivel : {0.0, 30 * kDeg, 70 * kDeg}) {
          SkeletonPose pose = rest;
          // The person faces -x (yaw pi): "in front" is world -x.
          const Vec3 target = S + Vec3(-fx, 0.05, dz);
          const ArmSolution sol = solve_arm(k, pose, side, {target, swivel, std::nullopt});
          EXPECT_TRUE(sol.reachable);
          EXPECT_LT((joint_position(k, pose, wrist(side)) - target).norm(), 1e-9);
          EXPECT_TRUE(check_joint_limits(pose).empty());
        }
      }
    }
  }
}

TEST(ArmIkTest, PositiveSwivelMovesTheElbowOutward) {
  const Skeleton k = Skeleton::FromHeight(1.70);
  const SkeletonPose rest = SkeletonPose::Standing(k, 0, 0, 0);
  for (const Side side : {Side::kLeft, Side::kRight}) {
    const Vec3 S = joint_position(k, rest, shoulder(side));
    const Vec3 target = S + Vec3(0.35, 0, -0.1);
    SkeletonPose down = rest;
    SkeletonPose out = rest;
    solve_arm(k, down, side, {target, 0, std::nullopt});
    solve_arm(k, out, side, {target, 60 * kDeg, std::nullopt});
    const double lateral = side == Side::kLeft ? 1.0 : -1.0;
    const Vec3 e_down = joint_position(k, down, elbow(side));
    const Vec3 e_out = joint_position(k, out, elbow(side));
    EXPECT_GT(lateral * (e_out.y() - e_down.y()), 0.05) << to_string(side);
    EXPECT_LT(e_down.z(), S.z());  // elbow below the shoulder with swivel 0
  }
}

TEST(ArmIkTest, UnreachableTargetsMakeTheArmPointAtThem) {
  const Skeleton k = Skeleton::FromHeight(1.70);
  SkeletonPose pose = SkeletonPose::Standing(k, 0, 0, 0);
  const Vec3 S = joint_position(k, pose, Joint::kRightShoulder);
  const Vec3 target = S + Vec3(1.0, -0.2, 0.1);
  const ArmSolution sol = solve_arm(k, pose, Side::kRight, {target, 0.3, std::nullopt});
  EXPECT_FALSE(sol.reachable);
  const Vec3 W = joint_position(k, pose, Joint::kRightWrist);
  const Vec3 n = (target - S).normalized();
  EXPECT_LT(((W - S) - (W - S).dot(n) * n).norm(), 1e-9);  // on the ray
  EXPECT_NEAR((W - S).norm(), 0.995 * arm_length(k, Side::kRight), 1e-9);
}

TEST(ArmIkTest, TargetsAtTheShoulderStopAtTheElbowLimit) {
  const Skeleton k = Skeleton::FromHeight(1.70);
  SkeletonPose pose = SkeletonPose::Standing(k, 0, 0, 0);
  const Vec3 S = joint_position(k, pose, Joint::kLeftShoulder);
  const ArmSolution sol = solve_arm(k, pose, Side::kLeft, {S + Vec3(0.05, 0, 0), 0.2, std::nullopt});
  EXPECT_FALSE(sol.reachable);
  EXPECT_NEAR(sol.elbow_flex, 145 * kDeg, 1e-9);
  EXPECT_TRUE(check_joint_limits(pose).empty());
}

TEST(ArmIkTest, HandOrientationTargetsAreMet) {
  const Skeleton k = Skeleton::FromHeight(1.80);
  const SkeletonPose rest = SkeletonPose::Standing(k, 0, 0, 0);
  for (const Side side : {Side::kLeft, Side::kRight}) {
    const Vec3 S = joint_position(k, rest, shoulder(side));
    SkeletonPose pose = rest;
    // Palm up and a little toward the midline, fingers forward (give me / receive).
    const Vec3 medial(0, side == Side::kLeft ? -0.5 : 0.5, 1);
    const Quat up = hand_rotation(side, Vec3::UnitX(), medial);
    solve_arm(k, pose, side, {S + Vec3(0.35, 0, -0.25), 20 * kDeg, up});
    const core::Pose X_W_wrist = forward_kinematics(k, pose)[static_cast<size_t>(index(wrist(side)))];
    EXPECT_LT((palm_normal(side, X_W_wrist) - medial.normalized()).norm(), 1e-6) << to_string(side);
    const Vec3 fingers = (index_tip(k, X_W_wrist) - X_W_wrist.translation).normalized();
    EXPECT_LT((fingers - Vec3::UnitX()).norm(), 1e-6);
    EXPECT_NEAR((palm_centre(k, X_W_wrist) - X_W_wrist.translation).norm(), k.palm_distance, 1e-12);
    EXPECT_TRUE(check_joint_limits(pose).empty());
  }
}

TEST(ArmIkTest, HandRotationIsClampedToTheWristLimits) {
  const Skeleton k = Skeleton::FromHeight(1.70);
  SkeletonPose pose = SkeletonPose::Standing(k, 0, 0, 0);
  const Vec3 S = joint_position(k, pose, Joint::kRightShoulder);
  // Fingers pointing back at the person: impossible for the wrist.
  const Quat back = hand_rotation(Side::kRight, -Vec3::UnitX(), Vec3::UnitZ());
  solve_arm(k, pose, Side::kRight, {S + Vec3(0.4, 0, -0.1), 0, back});
  EXPECT_TRUE(check_joint_limits(pose).empty());
}

TEST(ArmIkTest, TorsoLeansOnlyForFarReaches) {
  const Skeleton k = Skeleton::FromHeight(1.70);
  const SkeletonPose pose = SkeletonPose::Standing(k, 0, 0, 0);
  const Vec3 S = joint_position(k, pose, Joint::kRightShoulder);
  const double L = arm_length(k, Side::kRight);
  EXPECT_EQ(lean_for_reach(k, pose, Side::kRight, S + Vec3(0.5 * L, 0, 0), 0.93, 0.8), 0);
  const Vec3 far = S + Vec3(1.1 * L, 0, -0.3);
  const double lean = lean_for_reach(k, pose, Side::kRight, far, 0.93, 0.8);
  EXPECT_GT(lean, 0);
  EXPECT_LT(lean, 0.8);
  SkeletonPose leaned = pose;
  lean_spine(k, leaned, far - pose.X_WP.translation, lean);
  // The legs do not move.
  EXPECT_LT((joint_position(k, leaned, Joint::kLeftAnkle) - joint_position(k, pose, Joint::kLeftAnkle)).norm(), 1e-9);
  EXPECT_TRUE(check_joint_limits(leaned).empty());
  EXPECT_NEAR((far - joint_position(k, leaned, Joint::kRightShoulder)).norm(), 0.93 * L, 1e-6);
  // Leaning forward moves the head forward.
  EXPECT_GT(joint_position(k, leaned, Joint::kHead).x(), joint_position(k, pose, Joint::kHead).x());
  EXPECT_EQ(lean_for_reach(k, pose, Side::kRight, S + Vec3(5, 0, 0), 0.93, 0.8), 0.8);
}

TEST(ArmIkTest, JointLimitsFlagImpossiblePoses) {
  SkeletonPose pose;
  EXPECT_TRUE(check_joint_limits(pose).empty());
  pose.local[index(Joint::kLeftElbow)] = core::axis_angle(Vec3::UnitY(), 30 * kDeg);  // backwards
  pose.local[index(Joint::kSpine2)] = core::axis_angle(Vec3::UnitY(), 40 * kDeg);
  pose.local[index(Joint::kRightKnee)] = core::axis_angle(Vec3::UnitY(), -60 * kDeg);  // forward
  const auto v = check_joint_limits(pose);
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[0].joint, Joint::kLeftElbow);
  EXPECT_EQ(v[0].what, "elbow hyperextension");
  EXPECT_NEAR(v[0].value_deg, 30, 1e-9);
  EXPECT_EQ(v[0].limit_deg, 10);
  EXPECT_EQ(v[1].what, "spine");
  EXPECT_EQ(v[2].what, "knee hyperextension");
  // A normal elbow flexion is fine.
  SkeletonPose bent;
  bent.local[index(Joint::kRightElbow)] = core::axis_angle(Vec3(0, -1, 0), 100 * kDeg);
  EXPECT_TRUE(check_joint_limits(bent).empty());
}

TEST(ArmIkTest, SwingTwistDecomposition) {
  EXPECT_NEAR(twist_angle(core::axis_angle(Vec3::UnitZ(), 0.5), Vec3::UnitZ()), 0.5, 1e-12);
  EXPECT_NEAR(swing_angle(core::axis_angle(Vec3::UnitZ(), 0.5), Vec3::UnitZ()), 0, 1e-7);
  EXPECT_NEAR(twist_angle(core::axis_angle(Vec3::UnitX(), 0.4), Vec3::UnitZ()), 0, 1e-12);
  EXPECT_NEAR(swing_angle(core::axis_angle(Vec3::UnitX(), 0.4), Vec3::UnitZ()), 0.4, 1e-12);
  const Quat both = core::axis_angle(Vec3::UnitX(), 0.3) * core::axis_angle(Vec3::UnitZ(), -0.7);
  EXPECT_NEAR(twist_angle(both, Vec3::UnitZ()), -0.7, 1e-12);
}

// knee_bend's definition: the 60-step bisection of the thigh's tilt, each midpoint judged by
// rotating both bones (knee_bend skips the midpoints its closed form places for certain).
KneeBend knee_bend_by_bisection(const Skeleton& k, double forward, double crouch) {
  if (forward <= 0 || crouch <= 0) return {};
  const double flex = std::min(crouch * 0.7 * forward, 26 * kDeg);
  const Vec3& thigh = k.offset[static_cast<size_t>(index(Joint::kLeftKnee))];
  const Vec3& shin = k.offset[static_cast<size_t>(index(Joint::kLeftAnkle))];
  const auto ahead = [&](double b) {
    return (core::axis_angle(Vec3::UnitY(), -b) * thigh).x() +
           (core::axis_angle(Vec3::UnitY(), flex - b) * shin).x();
  };
  double lo = 0;
  double hi = flex;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (ahead(mid) > thigh.x() + shin.x() ? hi : lo) = mid;
  }
  return {lo, flex - lo};
}

TEST(ArmIkTest, KneeBendIsTheBisectionToTheBit) {
  int bent = 0;
  int at_flexion = 0;
  for (const double height : {1.5, 1.62, 1.75, 1.9}) {
    Skeleton k = Skeleton::FromHeight(height);
    for (int bones = 0; bones < 3; ++bones) {
      if (bones == 1) {
        // Bones that are not straight down (as a retargeted skeleton's may be).
        k.offset[static_cast<size_t>(index(Joint::kLeftKnee))] += Vec3(0.03, 0, 0.01);
        k.offset[static_cast<size_t>(index(Joint::kLeftAnkle))] += Vec3(-0.05, 0, 0);
      }
      if (bones == 2) {
        // No person's: a thigh almost level, so the ankle never comes ahead of where it was for
        // small bends and the bisection climbs all the way to the flexion.
        k.offset[static_cast<size_t>(index(Joint::kLeftKnee))] = Vec3(1.0, 0, -0.02);
      }
      for (int i = 0; i <= 400; ++i) {
        for (const double crouch : {0.0, 0.13, 0.5, 0.77, 1.0}) {
          const double forward = -0.1 + 1.4 * i / 400.0;
          const KneeBend fast = knee_bend(k, forward, crouch);
          const KneeBend slow = knee_bend_by_bisection(k, forward, crouch);
          ASSERT_EQ(fast.thigh, slow.thigh)
              << height << " m, bones " << bones << ", forward " << forward << ", crouch " << crouch;
          ASSERT_EQ(fast.shin, slow.shin);
          bent += fast.thigh > 0;
          at_flexion += fast.shin == 0 && fast.thigh > 0;
        }
      }
    }
  }
  EXPECT_GT(bent, 5000);
  EXPECT_GT(at_flexion, 100);
}

// lean_for_reach's definition: the 40-step bisection of the lean, each midpoint judged by
// leaning the pose (lean_for_reach skips the midpoints its bracket places for certain).
double lean_for_reach_by_bisection(const Skeleton& k, const SkeletonPose& pose, Side side, const Vec3& wrist,
                                   double max_lean, const Vec3& dir, double crouch) {
  const double reach = 0.93 * arm_length(k, side);
  const auto excess = [&](double angle) {
    SkeletonPose p = pose;
    lean_spine(k, p, dir, angle, crouch);
    return (wrist - joint_pose(k, p, shoulder(side)).translation).norm() - reach;
  };
  if (excess(0) <= 0) return 0;
  if (excess(max_lean) > 0) return max_lean;
  double lo = 0;
  double hi = max_lean;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (excess(mid) > 0 ? lo : hi) = mid;
  }
  return hi;
}

TEST(ArmIkTest, LeanForReachIsTheBisectionToTheBit) {
  core::Rng rng(3);
  int leaned = 0;
  for (int i = 0; i < 3000; ++i) {
    const Skeleton k = Skeleton::FromHeight(rng.uniform(1.5, 1.95));
    const SkeletonPose pose = SkeletonPose::Standing(k, rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2),
                                                     rng.uniform(-3, 3));
    const Side side = i % 2 == 0 ? Side::kLeft : Side::kRight;
    const Vec3 S = joint_pose(k, pose, shoulder(side)).translation;
    const double L = arm_length(k, side);
    // Targets in front of the person, from the chest's height to the floor's, 0.7 to 1.6 arm's
    // lengths ahead.
    const Vec3 ahead = pose.X_WP.rotation * Vec3(1, 0, 0);
    const Vec3 aside = pose.X_WP.rotation * Vec3(0, 1, 0);
    const Vec3 wrist = S + rng.uniform(0.7, 1.6) * L * ahead + rng.uniform(-0.6, 0.6) * L * aside +
                       Vec3(0, 0, -rng.uniform(0, 1.4) * L);
    Vec3 dir = pose.X_WP.rotation.conjugate() * (wrist - pose.X_WP.translation);
    dir.z() = 0;
    const double max_lean = rng.uniform(0.2, 70 * kDeg);
    const double crouch = i % 5 == 0 ? 0 : rng.uniform(0, 1);
    const double fast = lean_for_reach(k, pose, side, wrist, 0.93, max_lean, dir, crouch);
    ASSERT_EQ(fast, lean_for_reach_by_bisection(k, pose, side, wrist, max_lean, dir, crouch)) << "case " << i;
    leaned += fast > 0 && fast < max_lean;
  }
  EXPECT_GT(leaned, 600);  // solved by the bisection, not at an end
}

TEST(ArmIkTest, ALeanBendsTheKneesWithTheFeetFlatAndTheHipsAboveThem) {
  const Skeleton k = Skeleton::FromHeight(1.80);
  const SkeletonPose pose = SkeletonPose::Standing(k, 0.3, -0.2, 0.5);
  const Vec3 forward = Vec3::UnitX();  // pelvis frame
  SkeletonPose straight = pose;
  SkeletonPose crouched = pose;
  lean_spine(k, straight, forward, 0.6, 0);
  lean_spine(k, crouched, forward, 0.6, 1);
  const auto X0 = forward_kinematics(k, pose);
  const auto Xs = forward_kinematics(k, straight);
  const auto Xc = forward_kinematics(k, crouched);
  const auto at = [](const std::array<core::Pose, kNumJoints>& X, Joint j) {
    return X[static_cast<size_t>(index(j))];
  };
  const auto angle = [](const Quat& q) { return 2 * std::acos(std::min(1.0, std::abs(q.w()))); };
  // Knee flexion: 0.7 x the lean with crouch 1, none with crouch 0.
  EXPECT_NEAR(angle(crouched.local[static_cast<size_t>(index(Joint::kLeftKnee))]), 0.7 * 0.6, 1e-9);
  EXPECT_NEAR(angle(straight.local[static_cast<size_t>(index(Joint::kRightKnee))]), 0, 1e-9);
  for (const Joint ankle : {Joint::kLeftAnkle, Joint::kRightAnkle}) {
    // The feet stay in place and flat.
    EXPECT_LT((at(Xc, ankle).translation - at(X0, ankle).translation).norm(), 1e-9);
    EXPECT_LT(angle(at(Xc, ankle).rotation.conjugate() * at(X0, ankle).rotation), 1e-9);
  }
  // The hips drop straight down (the stand frame stays), and the shoulders come lower than with
  // straight legs.
  const Vec3 hip_c = 0.5 * (at(Xc, Joint::kLeftHip).translation + at(Xc, Joint::kRightHip).translation);
  const Vec3 hip_0 = 0.5 * (at(X0, Joint::kLeftHip).translation + at(X0, Joint::kRightHip).translation);
  EXPECT_LT(std::hypot(hip_c.x() - hip_0.x(), hip_c.y() - hip_0.y()), 1e-9);
  EXPECT_LT(hip_c.z(), hip_0.z() - 0.015);
  EXPECT_LT(at(Xc, Joint::kRightShoulder).translation.z(), at(Xs, Joint::kRightShoulder).translation.z() - 0.015);
  EXPECT_TRUE(check_joint_limits(crouched).empty());
  // The knee flexion is capped at 26 degrees.
  SkeletonPose deep = pose;
  lean_spine(k, deep, forward, 1.2, 1);
  EXPECT_NEAR(angle(deep.local[static_cast<size_t>(index(Joint::kLeftKnee))]), 26 * core::kPi / 180, 1e-9);
}

}  // namespace
}  // namespace hribench::human
