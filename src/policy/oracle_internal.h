#pragma once
// Internals shared by the expert's source files (policy/oracle*.cc): motion constants of the
// skills, object geometry by kind, small vector helpers and the indexed observation. Not part
// of the policy interface; include only from policy/oracle*.cc.

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/math.h"
#include "human/skeleton.h"
#include "model/model.h"
#include "policy/oracle.h"
#include "sim/distance.h"

namespace hribench::policy::oracle_internal {

using core::Pose;
using core::Quat;
using core::Vec3;

// The robot the skills are written for (grasp widths, hand clearances): the Panda and its hand.
// Another robot needs its own skills; the expert refuses its episodes (ExpertPolicy::reset).
inline const model::Robot& skill_robot() { return model::panda(); }

inline constexpr double kTableZ = model::kTableTopZ;
inline constexpr double kHoldingWidth = 0.004;   // m: an opening above this with the gripper closed holds
inline constexpr double kReachedDistance = 0.008;  // m: a segment's end counts as reached
inline constexpr double kCloseTime = 0.4;        // s of full grip before checking it
inline constexpr double kOpenTime = 0.5;         // s to open
inline constexpr double kPreshapeTime = 0.3;     // s to pre-shape the fingers before closing
// Then the commanded width shrinks slowly from kPreshapeGap over the object's width to
// kSqueezeDepth under it (the fingers meet the object slower than the metrics' "moving"
// gripper rate, 0.01 m/s), then drops to 0 (full grip force).
inline constexpr double kPreshapeGap = 0.004;    // m
inline constexpr double kSqueezeRate = 0.009;    // m/s
inline constexpr double kSqueezeDepth = 0.006;   // m
inline constexpr double kPalmDistance = 0.08;     // m: palm centre beyond the wrist along the forearm
inline constexpr double kHousingClearance = -0.03;  // m: TCP vs a container top (housing 0.044 above)
inline constexpr double kYieldSpeed = 0.6;         // m/s backing off from a disruption
// While yielding to an intruding person the oracle keeps the surface separation it estimates
// (intrusion_gap in oracle.cc: the robot's hand and wrist, the person's arms, hands, head and
// chest as capsules; within about 0.04 m of the simulator's d(t)) at least kProtectiveGap:
// docs/metrics.md's S_p of a resting robot near a person is 0.25 m. Below it the robot backs off,
// kIntrusionRetreatFactor times kRetreatSpeed; toward the yield pose it approaches the person
// no faster than S_p allows at the estimate less kGapMargin.
inline constexpr double kProtectiveGap = 0.31;     // m
inline constexpr double kGapMargin = 0.05;         // m
inline constexpr double kIntrusionRetreatFactor = 2.5;
inline constexpr double kHandReach = 0.19;         // m: a hand's extent around the wrist (any bend)

// Take (C1): an object a person holds out sits beside the palm as held from the start when
// it leans at most kTakeUprightTilt (rad) and its centre lies, from the wrist, this far along
// its x axis (the hand's direction) and this far across it (m; the palm distance and the hand's
// radius plus the object's, for every height and object kind).
inline constexpr double kTakeUprightTilt = 0.35;
inline constexpr std::pair<double, double> kTakeHandAlong = {0.03, 0.16};
inline constexpr std::pair<double, double> kTakeHandAcross = {0.03, 0.12};
// ... and the fingers close along the hand only for a grasp point less than kTakeHousingLow (m)
// above the object's centre (the hand's axis): the housing, 0.044 m over the TCP, otherwise
// clears the top of the hand (radius up to 0.04 m) by 4 cm whatever the finger axis.
inline constexpr double kTakeHousingLow = 0.04;
// The fingertips reach this far below the TCP (m); they come down past the top of an object
// held out only centred along the finger axis within the opening's slack less kTakeAlignMargin,
// else wait kTakeRimClearance over the top.
inline constexpr double kTakeFingertipsBelowTcp = 0.01;
inline constexpr double kTakeAlignMargin = 0.002;
inline constexpr double kTakeRimClearance = 0.01;
// The oracle keeps its hand and wrist kTakeHeadGap (m, estimated surface gap) from the head of
// a person leaning in (a ball of kTakeHeadRadius times the body's scale about the head joint,
// kTakeHeadTall high) while it waits for the object to be held still, kTakeHeadGapTaking while
// it comes in to take it (the estimate is within about 0.03 m of the simulator's), backing off
// below it and going on only where the gap stays above it (waiting: plus kTakeHeadResume);
// backing off, it goes down no lower than kTakeLowest over the table.
inline constexpr double kTakeHeadGap = 0.12;
inline constexpr double kTakeHeadGapTaking = 0.02;
inline constexpr double kTakeHeadResume = 0.03;
inline constexpr double kTakeHeadRadius = 0.1;
inline constexpr double kTakeHeadTall = 0.06;
inline constexpr double kTakeLowest = 0.25;

// Offer (C2, I2): the oracle keeps its hand and wrist (a capsule of kOfferWristRadius along
// the tool axis from kOfferWristFrom to kOfferWristTo over the TCP, m) kOfferHeadGap (m,
// estimated surface gap) from the head of a person leaning in over the receiving palm (the
// body model's head capsule: from kOfferHeadFrom to kOfferHeadTo of the neck-head offset past
// the neck, kOfferHeadRadius times the body's scale), leaning its wrist away by up to
// kOfferMaxTilt (rad) in steps of kOfferTiltStep.
inline constexpr double kOfferWristRadius = 0.06;
inline constexpr double kOfferWristFrom = 0.05;
inline constexpr double kOfferWristTo = 0.32;
inline constexpr double kOfferHeadFrom = 0.68;
inline constexpr double kOfferHeadTo = 1.26;
inline constexpr double kOfferHeadRadius = 0.095;
inline constexpr double kOfferHeadGap = 0.05;
inline constexpr double kOfferMaxTilt = 0.6;
inline constexpr double kOfferTiltStep = 0.1;
// Having let go, the oracle withdraws (kOfferWithdraw m, up as much as back toward the robot)
// once the fingers have opened kOfferFingersClear (m) wider than the object, after at least
// kOfferOpenAtLeast (s).
inline constexpr double kOfferWithdraw = 0.15;
inline constexpr double kOfferFingersClear = 0.016;
inline constexpr double kOfferOpenAtLeast = 0.1;
// Into a hand held out without a gesture, the TCP stays this far over its goal until the hand
// has been open for the receive act's `open` time (m).
inline constexpr double kOfferHoverAbove = 0.08;

inline bool is_container(const std::string& kind) { return kind == "bin" || kind == "tray" || kind == "box"; }

// Height of the TCP above an object's bottom for a top-down grasp (m), by kind.
inline double grasp_height(const std::string& kind, const Vec3& half) {
  if (kind == "bottle") return 0.18;   // the neck: the hand housing stays above the top
  if (kind == "cup") return 0.055;
  return half.z();
}

// Width of an object across the fingers of a top-down grasp (m).
inline double grip_width(const std::string& kind, const Vec3& half) {
  if (kind == "bottle") return 0.028;  // the neck
  return 2 * std::min(half.x(), half.y());
}

// Recovery: a round object knocked over (a bottle or cup whose axis is within 30 deg of
// horizontal: a person put it down badly) is grasped lying, across its body, the fingers
// across its axis, at kLyingGraspAlong of its length from its bottom (a bottle's body centre;
// a cup's middle), and carried with its axis along a container's length.
inline constexpr double kLyingGraspAlong = 0.43;
inline bool lying(const std::string& kind, const Pose& X_WO) {
  return (kind == "bottle" || kind == "cup") && (X_WO.rotation * Vec3::UnitZ()).z() < 0.5;
}
// The point on a lying object's axis where it is grasped (world).
inline Vec3 lying_grasp(const Pose& X_WO, const Vec3& half) {
  return X_WO * Vec3(0, 0, 2 * kLyingGraspAlong * half.z());
}
inline double wrap_half_turn(double a) {  // into [-pi/2, pi/2) modulo pi
  return a - core::kPi * std::floor((a + core::kPi / 2) / core::kPi);
}
// Recovery: the hand housing's half length along the finger axis and its bottom above the TCP
// (m), and the clearance from it to a neighbouring object below which a cube is grasped on its
// other pair of faces (when that is clearer).
inline constexpr double kHousingHalfLength = 0.1;
inline constexpr double kHousingAboveTcp = 0.044;
inline constexpr double kHousingClearanceWanted = 0.04;

// Rotation vector of R (axis * angle), angle in [0, pi].
inline Vec3 rotation_vector(const Quat& q) {
  const Eigen::AngleAxisd aa(q.normalized());
  double angle = aa.angle();
  Vec3 axis = aa.axis();
  if (angle > core::kPi) {
    angle = 2 * core::kPi - angle;
    axis = -axis;
  }
  return axis * angle;
}

inline double wrap_quarter(double a) {  // into [-pi/4, pi/4) modulo pi/2
  const double q = core::kPi / 2;
  return a - q * std::floor((a + q / 2) / q);
}

inline Vec3 clamp_norm(const Vec3& v, double limit) {
  const double n = v.norm();
  return n > limit ? Vec3(v * (limit / n)) : v;
}

// Distance from point p to segment ab.
inline double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b, Vec3& closest) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  closest = a + t * ab;
  return (p - closest).norm();
}

// A capsule of the oracle's own clearance estimates (a robot link, a body part): the points
// within `radius` of the axis a-b, m.
struct GapCapsule {
  Vec3 a, b;
  double radius = 0;
};

// The smallest surface gap between any capsule of `robot` and any of `body` (axis distance
// minus both radii; negative when they overlap), m. `away` becomes the unit direction from the
// body's nearest point to the robot's (the motion that increases the gap); it keeps its value
// where the axes touch.
template <size_t R, size_t B>
double surface_gap(const std::array<GapCapsule, R>& robot, const std::array<GapCapsule, B>& body, Vec3& away) {
  double gap = 1e9;
  for (const GapCapsule& r : robot) {
    for (const GapCapsule& h : body) {
      const sim::ClosestPoints axes = sim::closest_points(sim::Segment{r.a, r.b}, sim::Segment{h.a, h.b});
      const double d = axes.distance - r.radius - h.radius;
      if (d < gap) {
        gap = d;
        const Vec3 apart = axes.point_a_W - axes.point_b_W;
        if (apart.norm() > 1e-6) away = apart.normalized();
      }
    }
  }
  return gap;
}


// Index of an object by name in `objects` (anything with .name), or npos.
template <typename Objects>
size_t index_of(const Objects& objects, const std::string& name) {
  for (size_t k = 0; k < objects.size(); ++k) {
    if (objects[k].name == name) return k;
  }
  return static_cast<size_t>(-1);
}

}  // namespace hribench::policy::oracle_internal

namespace hribench::policy {

// The observation, indexed by the expert's object order.
struct ExpertPolicy::World {
  double time = 0;
  core::Pose X_WT;
  double width = 0;
  std::vector<core::Pose> objects;  // body frames (footprint centre, bottom), objects_ order
  std::array<core::Vec3, kHumanKeypoints> joints;
  double dt = 0.05;

  core::Vec3 centre(size_t i, const core::Vec3& half) const { return objects[i] * core::Vec3(0, 0, half.z()); }
  // Palm centre of a hand (0 left, 1 right) from the wrist and elbow.
  core::Vec3 palm(int side) const {
    const core::Vec3 wrist = joints[static_cast<size_t>(side == 0 ? human::index(human::Joint::kLeftWrist)
                                                            : human::index(human::Joint::kRightWrist))];
    const core::Vec3 elbow = joints[static_cast<size_t>(side == 0 ? human::index(human::Joint::kLeftElbow)
                                                            : human::index(human::Joint::kRightElbow))];
    const core::Vec3 forearm = wrist - elbow;
    return forearm.norm() > 1e-6 ? core::Vec3(wrist + oracle_internal::kPalmDistance * forearm.normalized()) : wrist;
  }
};

}  // namespace hribench::policy
