#include "human/skeleton.h"

#include <cmath>
#include <string>

#include "core/errors.h"

namespace hribench::human {
namespace {

using core::Vec3;

constexpr std::array<std::string_view, kNumJoints> kJointNames = {
    "pelvis",         "left_hip",       "right_hip",     "spine1",        "left_knee",
    "right_knee",     "spine2",         "left_ankle",    "right_ankle",   "spine3",
    "left_foot",      "right_foot",     "neck",          "left_collar",   "right_collar",
    "head",           "left_shoulder",  "right_shoulder", "left_elbow",   "right_elbow",
    "left_wrist",     "right_wrist"};

constexpr std::array<int, kNumJoints> kParents = {-1, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7,
                                                  8, 9, 9, 9, 12, 13, 14, 16, 17, 18, 19};

// Reference skeleton (HumanML3D lengths, docs/motion.md, left/right averaged), with
// anatomical rest directions in the body frame (x forward, y left, z up).
constexpr double kAnkleHeight = 0.06;     // ankle joint above the sole, m
constexpr double kCrownAboveNeck = 0.22;  // crown above the neck joint, m

struct Bone {
  double length;
  Vec3 direction;  // unnormalised
};

std::array<Bone, kNumJoints> reference_bones() {
  std::array<Bone, kNumJoints> b{};
  b[index(Joint::kPelvis)] = {0, Vec3::Zero()};
  b[index(Joint::kLeftHip)] = {0.1065, Vec3(0, 0.8, -0.6)};
  b[index(Joint::kRightHip)] = {0.1065, Vec3(0, -0.8, -0.6)};
  b[index(Joint::kSpine1)] = {0.132, Vec3(0, 0, 1)};
  b[index(Joint::kLeftKnee)] = {0.392, Vec3(0, 0, -1)};
  b[index(Joint::kRightKnee)] = {0.392, Vec3(0, 0, -1)};
  b[index(Joint::kSpine2)] = {0.143, Vec3(0, 0, 1)};
  b[index(Joint::kLeftAnkle)] = {0.429, Vec3(0, 0, -1)};
  b[index(Joint::kRightAnkle)] = {0.429, Vec3(0, 0, -1)};
  b[index(Joint::kSpine3)] = {0.057, Vec3(0, 0, 1)};
  b[index(Joint::kLeftFoot)] = {0.146, Vec3(0.92, 0, -0.4)};
  b[index(Joint::kRightFoot)] = {0.146, Vec3(0.92, 0, -0.4)};
  b[index(Joint::kNeck)] = {0.219, Vec3(0, 0, 1)};
  b[index(Joint::kLeftCollar)] = {0.1405, Vec3(0, 0.6, 0.8)};
  b[index(Joint::kRightCollar)] = {0.1405, Vec3(0, -0.6, 0.8)};
  b[index(Joint::kHead)] = {0.103, Vec3(0, 0, 1)};
  b[index(Joint::kLeftShoulder)] = {0.1275, Vec3(0, 1, 0)};
  b[index(Joint::kRightShoulder)] = {0.1275, Vec3(0, -1, 0)};
  b[index(Joint::kLeftElbow)] = {0.260, Vec3(0, 0, -1)};
  b[index(Joint::kRightElbow)] = {0.260, Vec3(0, 0, -1)};
  b[index(Joint::kLeftWrist)] = {0.268, Vec3(0, 0, -1)};
  b[index(Joint::kRightWrist)] = {0.268, Vec3(0, 0, -1)};
  return b;
}

}  // namespace

std::string_view joint_name(Joint joint) { return kJointNames[static_cast<size_t>(index(joint))]; }

std::optional<Joint> joint_from_name(std::string_view name) {
  for (int i = 0; i < kNumJoints; ++i) {
    if (kJointNames[static_cast<size_t>(i)] == name) return static_cast<Joint>(i);
  }
  return std::nullopt;
}

std::optional<Joint> parent(Joint joint) {
  const int p = kParents[static_cast<size_t>(index(joint))];
  if (p < 0) return std::nullopt;
  return static_cast<Joint>(p);
}

std::string_view to_string(Side side) { return side == Side::kLeft ? "left" : "right"; }
Joint wrist(Side side) { return side == Side::kLeft ? Joint::kLeftWrist : Joint::kRightWrist; }
Joint elbow(Side side) { return side == Side::kLeft ? Joint::kLeftElbow : Joint::kRightElbow; }
Joint shoulder(Side side) {
  return side == Side::kLeft ? Joint::kLeftShoulder : Joint::kRightShoulder;
}

std::string_view to_string(BodyRegion region) {
  switch (region) {
    case BodyRegion::kHead: return "head";
    case BodyRegion::kNeck: return "neck";
    case BodyRegion::kTorso: return "torso";
    case BodyRegion::kPelvis: return "pelvis";
    case BodyRegion::kUpperArm: return "upper_arm";
    case BodyRegion::kForearm: return "forearm";
    case BodyRegion::kHand: return "hand";
    case BodyRegion::kThigh: return "thigh";
    case BodyRegion::kShin: return "shin";
  }
  return "unknown";
}

double quasi_static_force_limit(BodyRegion region) {
  switch (region) {
    case BodyRegion::kHead: return 130;
    case BodyRegion::kNeck: return 150;
    case BodyRegion::kTorso: return 140;
    case BodyRegion::kPelvis: return 180;
    case BodyRegion::kUpperArm: return 150;
    case BodyRegion::kForearm: return 160;
    case BodyRegion::kHand: return 140;
    case BodyRegion::kThigh: return 220;
    case BodyRegion::kShin: return 130;
  }
  return 0;
}

Skeleton Skeleton::FromHeight(double height_m) {
  if (!(height_m >= 1.0 && height_m <= 2.5)) {
    throw core::InputError("human height", "a standing height in [1.0, 2.5] m",
                           std::to_string(height_m));
  }
  const auto bones = reference_bones();
  // Crown height of the reference skeleton: sole -> ankle -> knee -> hip -> pelvis (the hip
  // bone's vertical part) -> spine1..3 -> neck -> crown.
  const auto length = [&](Joint j) { return bones[static_cast<size_t>(index(j))].length; };
  const Vec3 hip_dir = bones[index(Joint::kLeftHip)].direction.normalized();
  const double reference_height = kAnkleHeight + length(Joint::kLeftAnkle) +
                                  length(Joint::kLeftKnee) - hip_dir.z() * length(Joint::kLeftHip) +
                                  length(Joint::kSpine1) + length(Joint::kSpine2) +
                                  length(Joint::kSpine3) + length(Joint::kNeck) + kCrownAboveNeck;
  const double s = height_m / reference_height;
  Skeleton k;
  k.height = height_m;
  for (int j = 1; j < kNumJoints; ++j) {
    const Bone& bone = bones[static_cast<size_t>(j)];
    k.offset[static_cast<size_t>(j)] = bone.direction.normalized() * (bone.length * s);
  }
  // Pelvis height: the vertical drop from the pelvis to the sole through the left leg.
  const double leg_drop = -(k.offset[index(Joint::kLeftHip)].z() +
                            k.offset[index(Joint::kLeftKnee)].z() +
                            k.offset[index(Joint::kLeftAnkle)].z());
  k.pelvis_height = leg_drop + kAnkleHeight * s;
  k.offset[index(Joint::kPelvis)] = Vec3(0, 0, k.pelvis_height);
  k.scale = s;
  k.crown_above_neck = kCrownAboveNeck * s;
  k.hand_length = 0.18 * s;
  k.palm_distance = 0.09 * s;
  return k;
}

SkeletonPose::SkeletonPose() { local.fill(core::Quat::Identity()); }

SkeletonPose SkeletonPose::Standing(const Skeleton& skeleton, double x, double y, double yaw_rad) {
  SkeletonPose pose;
  pose.X_WP.rotation = core::axis_angle(Vec3::UnitZ(), yaw_rad);
  pose.X_WP.translation = Vec3(x, y, skeleton.pelvis_height);
  return pose;
}

std::array<core::Pose, kNumJoints> forward_kinematics(const Skeleton& skeleton,
                                                      const SkeletonPose& pose) {
  std::array<core::Pose, kNumJoints> X_WJ;
  X_WJ[0] = pose.X_WP;
  // SMPL order lists every parent before its children.
  for (int j = 1; j < kNumJoints; ++j) {
    const auto uj = static_cast<size_t>(j);
    const core::Pose X_PJ{pose.local[uj], skeleton.offset[uj]};
    X_WJ[uj] = X_WJ[static_cast<size_t>(kParents[uj])] * X_PJ;
  }
  return X_WJ;
}

SkeletonPose interpolate(const SkeletonPose& a, const SkeletonPose& b, double s) {
  SkeletonPose out;
  out.X_WP.translation = (1 - s) * a.X_WP.translation + s * b.X_WP.translation;
  out.X_WP.rotation = a.X_WP.rotation.slerp(s, b.X_WP.rotation);
  for (size_t j = 0; j < out.local.size(); ++j) out.local[j] = a.local[j].slerp(s, b.local[j]);
  for (size_t h = 0; h < out.hands.size(); ++h) {
    out.hands[h] = {(1 - s) * a.hands[h].grip + s * b.hands[h].grip,
                    (1 - s) * a.hands[h].point + s * b.hands[h].point};
  }
  return out;
}

core::Pose joint_pose(const Skeleton& skeleton, const SkeletonPose& pose, Joint joint) {
  std::array<size_t, kNumJoints> chain;  // the joint, its parent, ..., below the pelvis
  size_t n = 0;
  for (int j = index(joint); j > 0; j = kParents[static_cast<size_t>(j)]) {
    chain[n++] = static_cast<size_t>(j);
  }
  core::Pose X_WJ = pose.X_WP;
  while (n > 0) {
    const size_t uj = chain[--n];
    X_WJ = X_WJ * core::Pose{pose.local[uj], skeleton.offset[uj]};
  }
  return X_WJ;
}

std::vector<BodyCapsule> body_capsules(const Skeleton& k) {
  const double s = k.scale;
  const auto off = [&](Joint j) { return k.offset[index(j)]; };
  const Vec3 zero = Vec3::Zero();
  std::vector<BodyCapsule> c;
  // Trunk.
  c.push_back({"pelvis", Joint::kPelvis, off(Joint::kLeftHip), off(Joint::kRightHip), 0.085 * s,
               BodyRegion::kPelvis});
  c.push_back({"abdomen", Joint::kSpine1, zero, off(Joint::kSpine2), 0.10 * s, BodyRegion::kTorso});
  c.push_back({"chest_low", Joint::kSpine2, zero, off(Joint::kSpine3), 0.11 * s, BodyRegion::kTorso});
  c.push_back({"chest", Joint::kSpine3, Vec3(0, 0.06 * s, 0.06 * s), Vec3(0, -0.06 * s, 0.06 * s),
               0.11 * s, BodyRegion::kTorso});
  c.push_back({"neck", Joint::kSpine3, Vec3(0, 0, 0.16 * s), off(Joint::kNeck), 0.05 * s,
               BodyRegion::kNeck});
  c.push_back({"head", Joint::kNeck, Vec3(0.01 * s, 0, 0.07 * s), Vec3(0.01 * s, 0, 0.13 * s),
               0.095 * s, BodyRegion::kHead});
  // Shoulder girdle and arms.
  for (const Side side : {Side::kLeft, Side::kRight}) {
    const bool left = side == Side::kLeft;
    const Joint collar = left ? Joint::kLeftCollar : Joint::kRightCollar;
    c.push_back({left ? "left_collar" : "right_collar", collar, zero, off(shoulder(side)),
                 0.05 * s, BodyRegion::kTorso});
    c.push_back({left ? "left_upper_arm" : "right_upper_arm", shoulder(side), zero,
                 off(elbow(side)), 0.045 * s, BodyRegion::kUpperArm});
    c.push_back({left ? "left_forearm" : "right_forearm", elbow(side), zero, off(wrist(side)),
                 0.038 * s, BodyRegion::kForearm});
    // The hand continues the forearm direction (-z of the wrist frame at rest).
    c.push_back({left ? "left_hand" : "right_hand", wrist(side), Vec3(0, 0, -0.03 * s),
                 Vec3(0, 0, -(k.hand_length - 0.035 * s)), 0.035 * s, BodyRegion::kHand});
  }
  // Legs.
  for (const Side side : {Side::kLeft, Side::kRight}) {
    const bool left = side == Side::kLeft;
    const Joint hip = left ? Joint::kLeftHip : Joint::kRightHip;
    const Joint knee = left ? Joint::kLeftKnee : Joint::kRightKnee;
    const Joint ankle = left ? Joint::kLeftAnkle : Joint::kRightAnkle;
    const Joint foot = left ? Joint::kLeftFoot : Joint::kRightFoot;
    c.push_back({left ? "left_thigh" : "right_thigh", hip, zero, off(knee), 0.07 * s,
                 BodyRegion::kThigh});
    c.push_back({left ? "left_shin" : "right_shin", knee, zero, off(ankle), 0.05 * s,
                 BodyRegion::kShin});
    c.push_back({left ? "left_foot" : "right_foot", ankle, Vec3(-0.03 * s, 0, -0.02 * s),
                 off(foot) + Vec3(0, 0, 0.02 * s), 0.035 * s, BodyRegion::kShin});
  }
  return c;
}

}  // namespace hribench::human
