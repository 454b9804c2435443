#include "human/arm_ik.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/bisection.h"
#include "core/errors.h"

namespace hribench::human {

using core::Quat;
using core::Vec3;

namespace {

double rotation_angle(const Quat& q) { return 2 * std::acos(std::min(1.0, std::abs(q.w()))); }

// Any unit vector perpendicular to a unit vector n.
Vec3 any_perpendicular(const Vec3& n) {
  const Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return n.cross(a).normalized();
}

// q = swing * twist about `axis` (unit, in q's own frame).
Quat twist_part(const Quat& q, const Vec3& axis) {
  const Vec3 p = q.vec().dot(axis) * axis;
  Quat t(q.w(), p.x(), p.y(), p.z());
  if (t.norm() < 1e-12) return Quat::Identity();
  return t.normalized();
}

// Limits a local rotation to |twist| <= max_twist about `axis` and swing <= max_swing.
Quat clamp_swing_twist(const Quat& q, const Vec3& axis, double max_twist, double max_swing) {
  const Quat twist = twist_part(q, axis);
  const Quat swing = (q * twist.conjugate()).normalized();
  const double tw = twist_angle(q, axis);
  const double sw = rotation_angle(swing);
  const Quat twist_c = core::axis_angle(axis, std::clamp(tw, -max_twist, max_twist));
  Quat swing_c = swing;
  if (sw > max_swing && swing.vec().norm() > 1e-12) {
    swing_c = core::axis_angle(swing.vec().normalized() * (swing.w() < 0 ? -1.0 : 1.0), max_swing);
  }
  return (swing_c * twist_c).normalized();
}

constexpr double kDeg = core::kPi / 180.0;

// Leaning (docs/motion.md, "Leaning"): the share of a forward lean at the hips, the knee
// flexion per radian of forward lean (at crouch 1) and its maximum (more let a short person's
// upper arm sink into the chest on a far, low reach).
constexpr double kHipShare = 0.4;
constexpr double kKneePerLean = 0.7;
constexpr double kMaxKneeBend = 26 * kDeg;

// The x coordinate of core::axis_angle(+y, angle) * v, to the bit, without the quaternion: the
// products that Eigen's rotation of a vector by the quaternion (cos(angle/2), sin(angle/2) +y)
// makes for x, less its exact zero terms (v + 2w (q x v) + 2 q x (q x v)).
double x_turned_about_y(double angle, const Vec3& v) {
  const double half = 0.5 * angle;
  const double c = std::cos(half);
  const double s = std::sin(half);
  const double uv_x = 2 * (s * v.z());
  const double uv_z = 2 * -(s * v.x());
  return (v.x() + c * uv_x) + s * uv_z;
}

// How far (m) a computed `ahead`, or the closed form's root times the slope, may be from the true
// value, with a wide margin: bones under a metre and a dozen operations round by about 1e-15 m.
constexpr double kAheadRounding = 1e-13;

}  // namespace

KneeBend knee_bend(const Skeleton& k, double forward, double crouch) {
  if (forward <= 0 || crouch <= 0) return {};
  const double flex = std::min(crouch * kKneePerLean * forward, kMaxKneeBend);
  const Vec3& thigh = k.offset[static_cast<size_t>(index(Joint::kLeftKnee))];
  const Vec3& shin = k.offset[static_cast<size_t>(index(Joint::kLeftAnkle))];
  // Forward distance of the ankle from the hip with the thigh tilted forward by b (increasing
  // in b), and at rest.
  const auto ahead = [&](double b) {
    return x_turned_about_y(-b, thigh) + x_turned_about_y(flex - b, shin);
  };
  const double rest = thigh.x() + shin.x();
  // In closed form (a turn by a about +y: x' = x cos a + z sin a), ahead(b) = P cos b + Q sin b
  // = R cos(b - phi), and its root on the rising side is phi - acos(rest / R). Where ahead rises
  // on all of [0, flex] (phi and phi - flex in (0, pi)), a midpoint farther from that root
  // than kAheadRounding / (the least slope) lies on the root's side whatever the rounding, so
  // only the midpoints closer to it are evaluated: the bisection's result to the bit, with about
  // a quarter of its 120 rotations (docs/performance.md "A leaning person's pose").
  const double cos_flex = std::cos(flex);
  const double sin_flex = std::sin(flex);
  const double P = thigh.x() + shin.x() * cos_flex + shin.z() * sin_flex;
  const double Q = -thigh.z() + shin.x() * sin_flex - shin.z() * cos_flex;
  const double R = std::hypot(P, Q);
  const double phi = std::atan2(Q, P);
  const double root = phi - std::acos(std::clamp(rest / R, -1.0, 1.0));
  const double least_slope = R * std::min(std::sin(phi), std::sin(phi - flex));
  const double sure =
      least_slope > 0 ? kAheadRounding / least_slope : std::numeric_limits<double>::infinity();
  // Once the midpoint rounds to an end the search has judged (any end but the first hi),
  // judging it again gives the same answer and nothing changes: the loop ends there.
  double lo = 0;
  double hi = flex;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    if ((mid == lo || mid == hi) && mid != flex) break;
    const bool past = std::abs(mid - root) > sure ? mid > root : ahead(mid) > rest;
    (past ? hi : lo) = mid;
  }
  return {lo, flex - lo};
}

Vec3 palm_centre(const Skeleton& skeleton, const core::Pose& X_W_wrist) {
  return X_W_wrist * Vec3(0, 0, -skeleton.palm_distance);
}

Vec3 index_tip(const Skeleton& skeleton, const core::Pose& X_W_wrist) {
  return X_W_wrist * Vec3(0, 0, -skeleton.hand_length);
}

Vec3 palm_normal(Side side, const core::Pose& X_W_wrist) {
  return X_W_wrist.rotation * Vec3(0, side == Side::kLeft ? -1.0 : 1.0, 0);
}

Quat hand_rotation(Side side, const Vec3& finger_dir, const Vec3& palm_dir) {
  const Vec3 f = finger_dir.normalized();
  Vec3 p = palm_dir - palm_dir.dot(f) * f;
  p = p.norm() > 1e-9 ? p.normalized() : any_perpendicular(f);
  // Columns: wrist-frame axes in world. z = -fingers; y = -palm (left) or +palm (right).
  const Vec3 z = -f;
  const Vec3 y = side == Side::kLeft ? -p : p;
  const Vec3 x = y.cross(z);
  core::Mat3 r;
  r.col(0) = x;
  r.col(1) = y;
  r.col(2) = z;
  return Quat(r).normalized();
}

double arm_length(const Skeleton& skeleton, Side side) {
  return skeleton.bone_length(elbow(side)) + skeleton.bone_length(wrist(side));
}

ArmSolution solve_arm(const Skeleton& skeleton, SkeletonPose& pose, Side side,
                      const ArmTarget& target) {
  const Joint sh = shoulder(side);
  const Joint el = elbow(side);
  const Joint wr = wrist(side);
  const core::Pose X_Wc = joint_pose(skeleton, pose, *parent(sh));
  const Quat R_torso = joint_pose(skeleton, pose, Joint::kSpine3).rotation;
  const Vec3 S = X_Wc * skeleton.offset[static_cast<size_t>(index(sh))];
  const double L1 = skeleton.bone_length(el);
  const double L2 = skeleton.bone_length(wr);

  // Reach distance, clamped to what the arm can do (Tolani step 1).
  ArmSolution out;
  const Vec3 d = target.wrist - S;
  double dist = d.norm();
  const Vec3 n = dist > 1e-9 ? Vec3(d / dist) : Vec3(R_torso * Vec3(0, 0, -1));
  // Closest: the elbow flexed to 145 degrees (human limit 150).
  const double lo = std::sqrt(L1 * L1 + L2 * L2 - 2 * L1 * L2 * std::cos(35 * kDeg));
  const double hi = 0.995 * (L1 + L2);
  if (dist > hi + 1e-9 || dist < lo - 1e-9) out.reachable = false;
  dist = std::clamp(dist, lo, hi);

  // Elbow on its swivel circle (Tolani steps 3-4): reference "down and slightly back" of the
  // torso, projected perpendicular to the shoulder-wrist axis.
  const double cos_a = std::clamp((L1 * L1 + dist * dist - L2 * L2) / (2 * L1 * dist), -1.0, 1.0);
  const double sin_a = std::sqrt(1 - cos_a * cos_a);
  const Vec3 ref = R_torso * Vec3(-0.3, 0, -1).normalized();
  Vec3 u = ref - ref.dot(n) * n;
  u = u.norm() > 1e-6 ? u.normalized() : any_perpendicular(n);
  const Vec3 v = n.cross(u);
  const Vec3 outward = side == Side::kLeft ? v : Vec3(-v);
  const Vec3 E = S + L1 * cos_a * n +
                 L1 * sin_a * (std::cos(target.swivel) * u + std::sin(target.swivel) * outward);
  const Vec3 W = S + dist * n;

  // Upper-arm frame: z = -(shoulder->elbow), x = the forearm's direction off the upper arm.
  const Vec3 u1 = (E - S).normalized();
  const Vec3 u2 = (W - E).normalized();
  Vec3 x = u2 - u2.dot(u1) * u1;
  x = x.norm() > 1e-9 ? x.normalized() : any_perpendicular(u1);
  const Vec3 z = -u1;
  const Vec3 y = z.cross(x);
  core::Mat3 r;
  r.col(0) = x;
  r.col(1) = y;
  r.col(2) = z;
  const Quat R_W_upper = Quat(r).normalized();
  pose.local[static_cast<size_t>(index(sh))] = (X_Wc.rotation.conjugate() * R_W_upper).normalized();

  // Elbow: flexion about the upper arm's -y axis brings the forearm toward +x.
  out.elbow_flex = std::acos(std::clamp(u1.dot(u2), -1.0, 1.0));
  const Quat elbow_q = core::axis_angle(Vec3(0, -1, 0), out.elbow_flex);
  pose.local[static_cast<size_t>(index(el))] = elbow_q;

  // Wrist: the requested hand rotation, within the wrist's limits.
  Quat wrist_q = Quat::Identity();
  if (target.hand) {
    const Quat R_W_fore = (R_W_upper * elbow_q).normalized();
    const Quat wanted = (R_W_fore.conjugate() * *target.hand).normalized();
    const Quat swing_only = (wanted * twist_part(wanted, Vec3::UnitZ()).conjugate()).normalized();
    wrist_q = clamp_swing_twist(wanted.slerp(std::clamp(target.free_roll, 0.0, 1.0), swing_only),
                                Vec3::UnitZ(), 85 * kDeg, 75 * kDeg);
  }
  pose.local[static_cast<size_t>(index(wr))] = wrist_q;
  return out;
}

void lean_spine(const Skeleton& skeleton, SkeletonPose& pose, const Vec3& direction,
                double angle, double crouch) {
  const Vec3 h(direction.x(), direction.y(), 0);
  if (h.norm() < 1e-9 || angle == 0) return;
  const Vec3 axis = Vec3::UnitZ().cross(h.normalized());
  const double forward = angle * h.normalized().x();  // the sagittal part, rad
  const auto joint = [&](Joint j) -> Quat& { return pose.local[static_cast<size_t>(index(j))]; };
  const auto ankle_mid = [&] {
    return Vec3(0.5 * (joint_pose(skeleton, pose, Joint::kLeftAnkle).translation +
                       joint_pose(skeleton, pose, Joint::kRightAnkle).translation));
  };
  const Vec3 feet = ankle_mid();
  // 40 % of the forward/backward part at the hips: the pelvis pitches and the thighs are
  // counter-rotated.
  const Quat pelvis_q = core::axis_angle(Vec3::UnitY(), kHipShare * forward);
  pose.X_WP.rotation = (pose.X_WP.rotation * pelvis_q).normalized();
  // A forward lean bends the knees (docs/motion.md, "Leaning"): the hips drop straight down,
  // the feet stay flat.
  const KneeBend bend = knee_bend(skeleton, forward, std::clamp(crouch, 0.0, 1.0));
  const Quat thigh_q = core::axis_angle(Vec3::UnitY(), -bend.thigh);
  const Quat knee_q = core::axis_angle(Vec3::UnitY(), bend.thigh + bend.shin);
  const Quat ankle_q = core::axis_angle(Vec3::UnitY(), -bend.shin);
  for (const Side side : {Side::kLeft, Side::kRight}) {
    const bool left = side == Side::kLeft;
    Quat& hip = joint(left ? Joint::kLeftHip : Joint::kRightHip);
    hip = (pelvis_q.conjugate() * thigh_q * hip).normalized();
    Quat& knee = joint(left ? Joint::kLeftKnee : Joint::kRightKnee);
    knee = (knee_q * knee).normalized();
    Quat& ankle = joint(left ? Joint::kLeftAnkle : Joint::kRightAnkle);
    ankle = (ankle_q * ankle).normalized();
  }
  // The rest of the lean, in equal shares at the spine joints.
  const Quat spine_q =
      (core::axis_angle(axis, angle / 3) *
       core::axis_angle(Vec3::UnitY(), -kHipShare * forward / 3)).normalized();
  for (Joint j : {Joint::kSpine1, Joint::kSpine2, Joint::kSpine3}) {
    Quat& q = joint(j);
    q = (spine_q * q).normalized();
  }
  // The feet stay where they were.
  pose.X_WP.translation += feet - ankle_mid();
}

double lean_for_reach(const Skeleton& skeleton, const SkeletonPose& pose, Side side,
                      const Vec3& wrist, double reach_fraction, double max_lean,
                      std::optional<Vec3> direction, double crouch) {
  const double reach = reach_fraction * arm_length(skeleton, side);
  const Vec3 dir = direction ? *direction
                             : Vec3(pose.X_WP.rotation.conjugate() * (wrist - pose.X_WP.translation));
  const auto excess = [&](double angle) {
    SkeletonPose p = pose;
    lean_spine(skeleton, p, dir, angle, crouch);
    return (wrist - joint_pose(skeleton, p, shoulder(side)).translation).norm() - reach;
  };
  const double at_zero = excess(0);
  if (at_zero <= 0) return 0;
  const double at_max = excess(max_lean);
  if (at_max > 0) return max_lean;
  return core::bisect_bracketed(0, at_zero, max_lean, at_max, 40, core::Crossing::kFalling, excess).hi;
}

double twist_angle(const Quat& q, const Vec3& axis) {
  double a = 2 * std::atan2(q.vec().dot(axis), q.w());
  if (a > core::kPi) a -= 2 * core::kPi;
  if (a < -core::kPi) a += 2 * core::kPi;
  return a;
}

double swing_angle(const Quat& q, const Vec3& axis) {
  return std::acos(std::clamp((q * axis).dot(axis), -1.0, 1.0));
}

std::vector<LimitViolation> check_joint_limits(const SkeletonPose& pose) {
  std::vector<LimitViolation> out;
  const auto check = [&](Joint j, const char* what, double value_rad, double limit_deg) {
    const double v = value_rad / kDeg;
    if (v > limit_deg + 1e-6) out.push_back({j, what, v, limit_deg});
  };
  const auto local = [&](Joint j) { return pose.local[static_cast<size_t>(index(j))]; };
  for (int j = 1; j < kNumJoints; ++j) {
    if (!pose.local[static_cast<size_t>(j)].coeffs().allFinite()) {
      out.push_back({static_cast<Joint>(j), "non-finite rotation", std::nan(""), 0});
    }
  }
  if (!out.empty()) return out;
  for (const Side side : {Side::kLeft, Side::kRight}) {
    // Shoulder: humeral rotation, and extension of the upper arm behind the body.
    const Quat qs = local(shoulder(side));
    check(shoulder(side), "shoulder humeral rotation", std::abs(twist_angle(qs, Vec3::UnitZ())), 110);
    const Vec3 ua = qs * Vec3(0, 0, -1);
    if (ua.x() < 0 && ua.z() < 0) {
      check(shoulder(side), "shoulder extension", std::atan2(-ua.x(), -ua.z()), 70);
    }
    // Elbow: flexion 0..150, at most 10 degrees of hyperextension, forearm roll <= 90.
    const Quat qe = local(elbow(side));
    const Vec3 fa = qe * Vec3(0, 0, -1);
    const double bend = std::acos(std::clamp(-fa.z(), -1.0, 1.0));
    check(elbow(side), fa.x() >= 0 ? "elbow flexion" : "elbow hyperextension", bend,
          fa.x() >= 0 ? 150 : 10);
    check(elbow(side), "elbow roll", std::abs(twist_angle(qe, Vec3::UnitZ())), 90);
    // Wrist: flexion/deviation and pro/supination.
    const Quat qw = local(wrist(side));
    check(wrist(side), "wrist swing", swing_angle(qw, Vec3::UnitZ()), 80);
    check(wrist(side), "wrist pro/supination", std::abs(twist_angle(qw, Vec3::UnitZ())), 90);
    check(side == Side::kLeft ? Joint::kLeftCollar : Joint::kRightCollar, "collar",
          rotation_angle(local(side == Side::kLeft ? Joint::kLeftCollar : Joint::kRightCollar)), 30);
  }
  for (Joint j : {Joint::kSpine1, Joint::kSpine2, Joint::kSpine3}) check(j, "spine", rotation_angle(local(j)), 30);
  for (Joint j : {Joint::kNeck, Joint::kHead}) check(j, "neck/head", rotation_angle(local(j)), 60);
  for (Joint j : {Joint::kLeftHip, Joint::kRightHip}) check(j, "hip", rotation_angle(local(j)), 110);
  for (Joint j : {Joint::kLeftKnee, Joint::kRightKnee}) {
    const Vec3 shin = local(j) * Vec3(0, 0, -1);
    const double bend = std::acos(std::clamp(-shin.z(), -1.0, 1.0));
    check(j, shin.x() <= 0 ? "knee flexion" : "knee hyperextension", bend, shin.x() <= 0 ? 150 : 10);
  }
  for (Joint j : {Joint::kLeftAnkle, Joint::kRightAnkle}) check(j, "ankle", rotation_angle(local(j)), 45);
  for (Joint j : {Joint::kLeftFoot, Joint::kRightFoot}) check(j, "foot", rotation_angle(local(j)), 30);
  return out;
}

}  // namespace hribench::human
