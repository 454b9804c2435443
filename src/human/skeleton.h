#pragma once
// The canonical human skeleton: the SMPL / HumanML3D 22-joint tree (docs/motion.md),
// with bone lengths scaled from a standing height, forward kinematics, and the capsule body
// that the model layer turns into MuJoCo geoms.
//
// Frames. Body frame (the pelvis frame at rest): x forward (the way the person faces), y to the
// person's left, z up; metres. Every joint has a frame; at rest (all local rotations identity)
// every joint frame is parallel to the body frame, the person stands upright with arms hanging
// down, and the soles of the feet are at z = 0 when the pelvis is at (0, 0, pelvis_height).
// HumanML3D's rest directions are y-up/+x-left/+z-forward; ours are the same directions under
// the proper rotation (x_h, y_h, z_h) -> (z_h, x_h, y_h).

#include <array>
#include <optional>
#include <string_view>
#include <vector>

#include "core/math.h"

namespace hribench::human {

inline constexpr int kNumJoints = 22;

// SMPL joint order (indices 0..21).
enum class Joint : int {
  kPelvis, kLeftHip, kRightHip, kSpine1, kLeftKnee, kRightKnee, kSpine2, kLeftAnkle,
  kRightAnkle, kSpine3, kLeftFoot, kRightFoot, kNeck, kLeftCollar, kRightCollar, kHead,
  kLeftShoulder, kRightShoulder, kLeftElbow, kRightElbow, kLeftWrist, kRightWrist,
};
inline constexpr int index(Joint j) { return static_cast<int>(j); }

// SMPL names: "pelvis", "left_hip", ..., "right_wrist".
std::string_view joint_name(Joint joint);
std::optional<Joint> joint_from_name(std::string_view name);
// Parent joint, or nullopt for the pelvis (the root).
std::optional<Joint> parent(Joint joint);

enum class Side { kLeft, kRight };
std::string_view to_string(Side side);
Joint wrist(Side side);
Joint elbow(Side side);
Joint shoulder(Side side);

// Body regions for contact grading against ISO/TS 15066 (docs/metrics.md, HCS).
enum class BodyRegion { kHead, kNeck, kTorso, kPelvis, kUpperArm, kForearm, kHand, kThigh, kShin };
inline constexpr int kNumBodyRegions = 9;
std::string_view to_string(BodyRegion region);  // "head", "neck", ..., "upper_arm", ...
// ISO/TS 15066 quasi-static force limit (N) for the region; transient = 2x. Torso uses the
// chest value (the lowest of back/shoulders and chest), pelvis the pelvis value, shin the
// lower-leg value (feet are graded as lower leg).
double quasi_static_force_limit(BodyRegion region);

// Joint offsets and shape of one person, scaled from a standing height.
struct Skeleton {
  double height = 0;          // standing height (floor to crown), m
  double pelvis_height = 0;   // height of the pelvis joint above the soles at rest, m
  // offset[j]: position of joint j's origin in its parent's frame (at rest: in the body
  // frame). offset[pelvis] = (0, 0, pelvis_height).
  std::array<core::Vec3, kNumJoints> offset{};
  double scale = 1;           // this skeleton's lengths / the reference skeleton's
  double crown_above_neck = 0;  // crown height above the neck joint at rest, m
  double hand_length = 0;     // wrist to fingertip, m (along the forearm direction)
  double palm_distance = 0;   // wrist to the palm centre (where a held object sits), m

  // Scales the reference (HumanML3D, about 1.72 m crown height) skeleton to `height_m`.
  // Throws core::InputError unless 1.0 <= height_m <= 2.5.
  static Skeleton FromHeight(double height_m);
  // Length of the bone from joint j's parent to j.
  double bone_length(Joint joint) const { return offset[index(joint)].norm(); }
};

// The shape of one hand (docs/motion.md "Hands"): how far the fingers close and whether the
// index points. human/hand.h turns it into the frames of the drawn fingers.
struct HandShape {
  double grip = 0;   // 0 = open (fingers almost straight) .. 1 = closed around an object
  double point = 0;  // 0 .. 1 = the index straight, the other fingers and the thumb folded in
  bool operator==(const HandShape&) const = default;
};

// One pose of the skeleton.
struct SkeletonPose {
  core::Pose X_WP;  // pose of the pelvis frame in world
  // Rotation of each joint's frame relative to its parent's frame; identity = rest.
  // local[pelvis] is ignored (the root rotation is X_WP.rotation).
  std::array<core::Quat, kNumJoints> local;
  std::array<HandShape, 2> hands{};  // [0] left, [1] right

  SkeletonPose();  // rest pose at the world origin, feet on z = 0 is NOT implied (X_WP = I)
  // Rest pose standing on the floor at (x, y), facing yaw_rad about +z.
  static SkeletonPose Standing(const Skeleton& skeleton, double x, double y, double yaw_rad);
};

// World pose of every joint frame: X_WJ = X_W,parent * (local[j], offset[j]).
std::array<core::Pose, kNumJoints> forward_kinematics(const Skeleton& skeleton,
                                                      const SkeletonPose& pose);
// World pose of one joint frame, forward_kinematics(skeleton, pose)[index(joint)] to the bit:
// the same products in the same order, along the joint's own chain only (3-7 of the 21). For
// the inner loops of the lean (human/motion.cc), which need an ankle, a shoulder or the neck.
core::Pose joint_pose(const Skeleton& skeleton, const SkeletonPose& pose, Joint joint);

// The pose a share s (0..1) of the way from a to b: the root's position and the hands' shapes
// linear, the root's and every joint's rotation slerped.
SkeletonPose interpolate(const SkeletonPose& a, const SkeletonPose& b, double s);

// A capsule of the human body, rigidly attached to one joint frame.
struct BodyCapsule {
  std::string_view name;  // e.g. "left_forearm"
  Joint joint;            // the frame it is attached to
  core::Vec3 from;        // segment end points in that joint's frame, m
  core::Vec3 to;
  double radius;          // m
  BodyRegion region;
};

// The capsule body of a skeleton (pelvis, torso, neck, head, collars, arms, hands, legs,
// feet), about 20 capsules. Deterministic order.
std::vector<BodyCapsule> body_capsules(const Skeleton& skeleton);

}  // namespace hribench::human
