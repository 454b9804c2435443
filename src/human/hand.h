#pragma once
// The drawn hand (docs/motion.md "Hands"): a palm, an index finger, the three other fingers and
// a thumb, as capsules, posed from a HandShape, so that a pointing hand, an open palm and a
// closed hand differ in silhouette. The hand's contact shape stays the one capsule of
// body_capsules() ("left_hand" / "right_hand"), within 5.5 cm of these parts in every shape; the
// drawn parts are seen by cameras and never touch anything.
//
// Frames: every part has a frame given relative to its wrist joint frame. In the wrist frame the
// fingers point along -z, the thumb lies on the +x side and the palm faces -y for the left hand,
// +y for the right (toward the midline at rest: human::palm_normal). A finger flexes
// toward the palm. Each part's capsules run along -z of its own frame.

#include <array>
#include <string_view>
#include <vector>

#include "core/math.h"
#include "human/skeleton.h"

namespace hribench::human {

// The parts of a hand, each one rigid frame: the palm, the index's proximal and distal
// segments, the other three fingers' proximal and distal segments (one frame for the three),
// and the thumb's two segments.
enum class HandPart {
  kPalm, kIndexProximal, kIndexDistal, kFingersProximal, kFingersDistal, kThumbProximal,
  kThumbDistal,
};
inline constexpr int kNumHandParts = 7;
std::string_view to_string(HandPart part);  // "palm", "index_proximal", ...

// A capsule of the drawn hand, in its part's frame.
struct HandCapsule {
  HandPart part;
  core::Vec3 from;
  core::Vec3 to;
  double radius;  // m
};

// The drawn hand's capsules (the same for both sides), scaled with the skeleton; fully
// straightened they reach Skeleton::hand_length from the wrist, as the contact capsule does.
std::vector<HandCapsule> hand_capsules(const Skeleton& skeleton);

// The frame of every part relative to the wrist joint frame (X_wrist_part), for a hand of
// `side` in `shape` (grip and point are clamped to [0, 1]).
std::array<core::Pose, kNumHandParts> hand_part_frames(const Skeleton& skeleton, Side side,
                                                       const HandShape& shape);

// The world pose of every part of both hands ([0] left, [1] right) of a posed skeleton whose
// joint frames are X_WJ (forward_kinematics(skeleton, pose)).
std::array<std::array<core::Pose, kNumHandParts>, 2> hand_part_poses(
    const Skeleton& skeleton, const SkeletonPose& pose,
    const std::array<core::Pose, kNumJoints>& X_WJ);

}  // namespace hribench::human
