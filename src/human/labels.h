#pragma once
// Checks on a human clip that the validator runs before any physics (docs/scenario-scripts.md "Labels"):
// the pointing ray passes through a target's cue region, a hand stays still inside a zone for a
// phase, an intruding hand enters the workspace, no self-penetration of the capsule body, joint
// angles within human limits, bone lengths preserved. Each check returns a CheckResult whose
// message names the phase, the worst value and when it happened.
//
// Per-frame labels (phase, active hand, grips and held objects) come with the clip from the
// generator (human/motion.h, LabelledClip).

#include <optional>
#include <string>

#include "core/math.h"
#include "human/clip.h"
#include "human/motion.h"

namespace hribench::human {

struct CheckResult {
  bool ok = true;
  double worst = 0;      // the worst value seen (unit of the check, see each function)
  double time = 0;       // clip time of the worst value, s
  std::string message;   // empty when ok, else one line, e.g. "point.hold: ray misses ..."
};

// Which point of a hand a check follows (human/arm_ik.h defines them).
enum class HandPoint { kWrist, kPalm, kIndexTip };
// Parses "wrist" | "palm" (or "hand") | "index"; nullopt otherwise.
std::optional<HandPoint> hand_point_from_name(std::string_view name);
core::Vec3 hand_point(const Skeleton& skeleton, const SkeletonPose& pose, Side side,
                      HandPoint point);

// Distance (m) from `target` to the pointing ray shoulder -> index fingertip of `side` (to the
// shoulder itself when the target is behind it).
double pointing_ray_distance(const Skeleton& skeleton, const SkeletonPose& pose, Side side,
                             const core::Vec3& target);
// Shoulder-wrist distance / (upper arm + forearm): pointing "extension".
double arm_extension(const Skeleton& skeleton, const SkeletonPose& pose, Side side);

// Every frame of `phase`: the pointing ray passes within `radius` of `target`.
// worst = largest distance (m).
CheckResult check_pointing(const Clip& clip, Side side, const core::Vec3& target, double radius,
                           const std::string& phase = "hold");

// Every frame of `phase`: the hand point is inside the zone and moves slower than
// `max_speed` (m/s, finite differences between frames). worst = largest speed (m/s), or the
// largest distance outside the zone (m) when that is the failure.
CheckResult check_stable_in_zone(const Clip& clip, Side side, HandPoint point, const Zone& zone,
                                 const std::string& phase, double max_speed = 0.05);

// An axis-aligned box in the world frame (the shared workspace).
struct Box {
  core::Vec3 min = core::Vec3::Zero();
  core::Vec3 max = core::Vec3::Zero();
  bool contains(const core::Vec3& p) const;
};
// The hand point starts outside `box` and is inside it at some frame of `phase` (whole clip when
// phase is empty): it crossed the workspace boundary. worst = time of entry (s), or the closest
// approach (m) when it never entered.
CheckResult check_enters_box(const Clip& clip, Side side, HandPoint point, const Box& box,
                             const std::string& phase = "");

// Shortest distance between segments [p0, p1] and [q0, q1] (m).
double segment_distance(const core::Vec3& p0, const core::Vec3& p1, const core::Vec3& q0,
                        const core::Vec3& q1);
// No two body capsules (human::body_capsules) more than two joints apart in the tree overlap by
// more than `tolerance` (m) in any frame. worst = deepest overlap (m, > 0 = penetration).
CheckResult check_self_penetration(const Clip& clip, double tolerance = 0.005);

// Every frame within check_joint_limits (human/arm_ik.h). worst = largest excess (deg).
CheckResult check_clip_joint_limits(const Clip& clip);

// Every frame's bone lengths (distance of each joint to its parent, from forward kinematics)
// equal the skeleton's within `tolerance` (m). worst = largest error (m).
CheckResult check_bone_lengths(const Clip& clip, double tolerance = 1e-6);

}  // namespace hribench::human
