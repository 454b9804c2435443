// The drawn hand: capsules and part frames from a HandShape (docs/motion.md "Hands").
//
// Proportions (at scale 1, a 1.72 m person): palm 0.095 m from the wrist to the knuckles, 7 cm
// across and 3.2 cm thick; fingers of 4.5 + 3-4.2 cm, the index reaching 0.18 m from the wrist
// (Skeleton::hand_length) when straight; a thumb of 5 + 3.2 cm from the base of the palm.
// A relaxed open hand keeps its fingers 15 % of the way to a wrap; a closed hand wraps an object
// (60 deg at the knuckle, 70 deg at the middle joint); a pointing hand makes a fist of the other
// fingers (85 and 100 deg) and lays the thumb across them.

#include "human/hand.h"

#include <algorithm>

#include "human/arm_ik.h"

namespace hribench::human {
namespace {

using core::Pose;
using core::Quat;
using core::Vec3;

constexpr double kRelaxed = 0.15;  // curl of an open hand, as a fraction of a wrap
constexpr double kWrapKnuckle = core::deg_to_rad(60);
constexpr double kWrapMiddle = core::deg_to_rad(70);
constexpr double kFistKnuckle = core::deg_to_rad(85);
constexpr double kFistMiddle = core::deg_to_rad(100);
constexpr double kThumbTipFlex = core::deg_to_rad(40);

// Lengths at scale 1, m.
constexpr double kKnuckle = 0.095;      // wrist to the knuckle line
constexpr double kProximal = 0.045;     // every finger's proximal segment
constexpr double kIndexDistal = 0.04;   // so the straight index ends at hand_length (0.18)
constexpr double kIndexX = 0.024;       // the index's offset toward the thumb side
constexpr double kThumbProximal = 0.05;
constexpr double kThumbDistal = 0.032;

// The three other fingers: offset toward the thumb side, distal length, radius (scale 1, m).
struct OtherFinger {
  double x;
  double distal;
  double radius;
};
constexpr std::array<OtherFinger, 3> kOtherFingers = {{
    {0.005, 0.042, 0.008},    // middle
    {-0.013, 0.04, 0.0078},   // ring
    {-0.029, 0.03, 0.007},    // little
}};

Quat along(const Vec3& direction) {
  return Quat::FromTwoVectors(-Vec3::UnitZ(), direction.normalized());
}

}  // namespace

std::string_view to_string(HandPart part) {
  switch (part) {
    case HandPart::kPalm: return "palm";
    case HandPart::kIndexProximal: return "index_proximal";
    case HandPart::kIndexDistal: return "index_distal";
    case HandPart::kFingersProximal: return "fingers_proximal";
    case HandPart::kFingersDistal: return "fingers_distal";
    case HandPart::kThumbProximal: return "thumb_proximal";
    case HandPart::kThumbDistal: return "thumb_distal";
  }
  return "?";
}

std::vector<HandCapsule> hand_capsules(const Skeleton& skeleton) {
  const double s = skeleton.scale;
  const auto segment = [s](HandPart part, double x, double length, double radius) {
    return HandCapsule{part, Vec3(x * s, 0, 0), Vec3(x * s, 0, -length * s), radius * s};
  };
  std::vector<HandCapsule> c;
  // The palm: two capsules side by side, on the index side and on the little finger's side.
  c.push_back({HandPart::kPalm, Vec3(0.018 * s, 0, -0.03 * s), Vec3(0.021 * s, 0, -0.088 * s),
               0.016 * s});
  c.push_back({HandPart::kPalm, Vec3(-0.012 * s, 0, -0.03 * s), Vec3(-0.019 * s, 0, -0.085 * s),
               0.016 * s});
  c.push_back(segment(HandPart::kIndexProximal, kIndexX, kProximal, 0.0085));
  c.push_back(segment(HandPart::kIndexDistal, kIndexX, kIndexDistal, 0.0085));
  for (const OtherFinger& f : kOtherFingers) {
    c.push_back(segment(HandPart::kFingersProximal, f.x, kProximal, f.radius));
    c.push_back(segment(HandPart::kFingersDistal, f.x, f.distal, f.radius));
  }
  c.push_back(segment(HandPart::kThumbProximal, 0, kThumbProximal, 0.0095));
  c.push_back(segment(HandPart::kThumbDistal, 0, kThumbDistal, 0.009));
  return c;
}

std::array<Pose, kNumHandParts> hand_part_frames(const Skeleton& skeleton, Side side,
                                                 const HandShape& shape) {
  const double s = skeleton.scale;
  const double grip = std::clamp(shape.grip, 0.0, 1.0);
  const double point = std::clamp(shape.point, 0.0, 1.0);
  const Vec3 fingers = -Vec3::UnitZ();
  const Vec3 normal = palm_normal(side, Pose::Identity());  // in the wrist frame
  const Vec3 thumb_side = Vec3::UnitX();
  // A finger flexes toward the palm: about fingers x normal.
  const Vec3 flex_axis = fingers.cross(normal);

  std::array<Pose, kNumHandParts> X;
  const auto part = [&X](HandPart p) -> Pose& { return X[static_cast<size_t>(p)]; };
  // A two-segment finger from the knuckle line, bent by `knuckle` and `middle` (rad).
  const auto finger = [&](HandPart proximal, HandPart distal, double knuckle, double middle) {
    part(proximal) = Pose{core::axis_angle(flex_axis, knuckle), Vec3(0, 0, -kKnuckle * s)};
    part(distal) = part(proximal) * Pose{core::axis_angle(flex_axis, middle), Vec3(0, 0, -kProximal * s)};
  };
  const double wrap = (1 - point) * (kRelaxed + (1 - kRelaxed) * grip);
  finger(HandPart::kIndexProximal, HandPart::kIndexDistal, wrap * kWrapKnuckle, wrap * kWrapMiddle);
  finger(HandPart::kFingersProximal, HandPart::kFingersDistal,
         wrap * kWrapKnuckle + point * kFistKnuckle, wrap * kWrapMiddle + point * kFistMiddle);

  // The thumb swings from spread (open hand) to across the palm's front (closed or pointing).
  const double closed = std::max(grip, point);
  const Quat spread = along(0.7 * fingers + 0.6 * thumb_side + 0.1 * normal);
  const Quat across = along(0.8 * fingers + 0.55 * normal - 0.2 * thumb_side);
  const Quat R = spread.slerp(closed, across).normalized();
  part(HandPart::kThumbProximal) = Pose{R, Vec3(0.02 * s, 0, -0.025 * s) + 0.015 * s * normal};
  const Vec3 direction = R * fingers;
  const Vec3 tip_axis = R.conjugate() * direction.cross(normal).normalized();
  part(HandPart::kThumbDistal) =
      part(HandPart::kThumbProximal) *
      Pose{core::axis_angle(tip_axis, closed * kThumbTipFlex), Vec3(0, 0, -kThumbProximal * s)};
  return X;
}

std::array<std::array<Pose, kNumHandParts>, 2> hand_part_poses(
    const Skeleton& skeleton, const SkeletonPose& pose,
    const std::array<Pose, kNumJoints>& X_WJ) {
  std::array<std::array<Pose, kNumHandParts>, 2> X_W;
  for (const Side side : {Side::kLeft, Side::kRight}) {
    const size_t h = side == Side::kLeft ? 0 : 1;
    const Pose& X_W_wrist = X_WJ[static_cast<size_t>(index(wrist(side)))];
    const auto X_wrist = hand_part_frames(skeleton, side, pose.hands[h]);
    for (size_t p = 0; p < X_wrist.size(); ++p) X_W[h][p] = X_W_wrist * X_wrist[p];
  }
  return X_W;
}

}  // namespace hribench::human
