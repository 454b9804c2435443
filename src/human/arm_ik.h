#pragma once
// Analytic two-link arm IK with an elbow swivel angle (Tolani, Goswami & Badler 2000;
// docs/motion.md), hand orientation targets, torso lean for far reaches, and human
// joint-angle limits. Everything writes SkeletonPose::local rotations in the skeleton's
// convention (identity = rest, arms hanging, body frame x forward / y left / z up).
//
// Hand frame: the wrist joint frame. At rest the fingers point along -z of the wrist frame and
// the palm faces the body's midline: palm normal -y for the left hand, +y for the right.
// Points on the hand (wrist frame): palm centre (0, 0, -palm_distance), index fingertip
// (0, 0, -hand_length) (Skeleton fields).

#include <optional>
#include <string>
#include <vector>

#include "human/skeleton.h"

namespace hribench::human {

// Points of a hand in world, from the wrist frame X_W_wrist.
core::Vec3 palm_centre(const Skeleton& skeleton, const core::Pose& X_W_wrist);
core::Vec3 index_tip(const Skeleton& skeleton, const core::Pose& X_W_wrist);
// Unit palm normal (the direction the palm faces) in world.
core::Vec3 palm_normal(Side side, const core::Pose& X_W_wrist);

// World rotation of a hand (wrist frame) whose fingers point along `finger_dir` and whose palm
// faces `palm_dir` (made perpendicular to the fingers). Both in world, any length > 0, not
// parallel.
core::Quat hand_rotation(Side side, const core::Vec3& finger_dir, const core::Vec3& palm_dir);

struct ArmTarget {
  core::Vec3 wrist;  // desired wrist joint position, world, m
  // Elbow swivel about the shoulder-wrist axis, rad: 0 = elbow at the bottom of its circle
  // (toward "down and slightly back" of the torso), positive = elbow out, away from the body.
  double swivel = 0;
  // Desired world rotation of the hand (wrist frame); nullopt keeps the wrist straight.
  std::optional<core::Quat> hand;
  // In [0, 1]: how much of the hand's roll about the fingers is left to the forearm. 1 imposes
  // only the finger direction (pointing), 0 the whole rotation.
  double free_roll = 0;
};

struct ArmSolution {
  bool reachable = true;  // false: the wrist was out of reach and the arm points at it instead
  double elbow_flex = 0;  // rad, 0 = straight
};

// Upper-arm + forearm length of that arm.
double arm_length(const Skeleton& skeleton, Side side);

// Writes pose.local for the shoulder, elbow and wrist of `side` (the collar and everything
// above it are read, not changed). The wrist target is clamped to a reach between an elbow
// flexion of 145 degrees and 0.995 (L1+L2); the hand rotation is clamped to the wrist limits.
ArmSolution solve_arm(const Skeleton& skeleton, SkeletonPose& pose, Side side,
                      const ArmTarget& target);

// The knees' bend in a forward lean of `forward` rad (its sagittal part) with `crouch` in
// [0, 1]: the knee flexes by crouch * 0.7 * forward (at most 26 degrees), as forward tilts of
// the thighs and the shins whose sum is that flexion. The thigh's share is the one that keeps
// the hips straight above where they were (the hips only drop), with the skeleton's own bone
// directions: the 60-step bisection of the thigh's tilt over [0, flexion] (lean_spine uses it).
struct KneeBend {
  double thigh = 0;  // rad
  double shin = 0;   // rad
};
KneeBend knee_bend(const Skeleton& skeleton, double forward, double crouch);

// A lean of `angle` rad toward `direction` (pelvis frame, only its xy part is used) about the
// horizontal axis perpendicular to it: 40 % of its forward part at the hips (the pelvis pitches,
// the thighs are counter-rotated), the rest in equal shares at spine1..spine3. A forward lean
// also bends the knees by `crouch` (in [0, 1]) times 0.7 times the lean (at most 26 degrees): the hips
// drop straight down (they stay above where they were, so the stand frame does not move), the
// thighs and shins tilt forward, the feet stay flat (docs/motion.md, "Leaning"). The ankles do
// not move. Composes with what the pose already has; call it once per pose.
void lean_spine(const Skeleton& skeleton, SkeletonPose& pose, const core::Vec3& direction,
                double angle, double crouch = 1);

// Smallest lean (rad, at most max_lean) toward `direction` (pelvis frame; default: toward the
// wrist target) with that crouch (lean_spine) that brings the shoulder of `side` within
// reach_fraction * arm_length of `wrist` (world); 0 when already within reach. `pose` is not
// leaned yet.
double lean_for_reach(const Skeleton& skeleton, const SkeletonPose& pose, Side side,
                      const core::Vec3& wrist, double reach_fraction, double max_lean,
                      std::optional<core::Vec3> direction = std::nullopt, double crouch = 1);

// Human joint-angle limits (degrees), generous ranges from clinical norms: elbow flexion
// 0-150 (hyperextension <= 10), wrist swing <= 80 and pro/supination <= 90, shoulder humeral
// rotation <= 110 and extension behind the body <= 70, each spine joint <= 30, neck/head <= 60,
// collar <= 30, hip <= 110, knee flexion 0-150, ankle <= 45, foot <= 30. A non-finite rotation
// is reported as "non-finite rotation" (value NaN) and nothing else is checked.
struct LimitViolation {
  Joint joint;
  std::string what;  // e.g. "elbow flexion"
  double value_deg;
  double limit_deg;
};
std::vector<LimitViolation> check_joint_limits(const SkeletonPose& pose);

// Swing-twist decomposition of a rotation about a unit axis: twist angle (rad, in [-pi, pi])
// about the axis, and swing angle (rad, in [0, pi]) of the axis itself.
double twist_angle(const core::Quat& q, const core::Vec3& axis);
double swing_angle(const core::Quat& q, const core::Vec3& axis);

}  // namespace hribench::human
