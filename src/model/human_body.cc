// The kinematic human: one mocap body per skeleton joint, carrying that joint's capsules.

#include <string>
#include <vector>

#include <fmt/format.h>

#include "human/hand.h"
#include "model/mjcf.h"

namespace hribench::model::mjcf {
namespace {

// Colours by region: skin for head, neck and hands; shirt for torso and arms; trousers below.
std::string_view region_rgba(human::BodyRegion region) {
  switch (region) {
    case human::BodyRegion::kHead:
    case human::BodyRegion::kNeck:
    case human::BodyRegion::kHand:
      return "0.87 0.68 0.55 1";
    case human::BodyRegion::kTorso:
    case human::BodyRegion::kUpperArm:
    case human::BodyRegion::kForearm:
      return "0.25 0.45 0.7 1";
    case human::BodyRegion::kPelvis:
    case human::BodyRegion::kThigh:
    case human::BodyRegion::kShin:
      return "0.2 0.2 0.25 1";
  }
  return "0.5 0.5 0.5 1";
}

}  // namespace

void human_body(const human::Skeleton& skeleton, const std::vector<human::BodyCapsule>& capsules,
                const human::SkeletonPose& pose, const std::array<core::Pose, 2>& X_wrist_palm,
                std::string& worldbody) {
  const auto X_WJ = human::forward_kinematics(skeleton, pose);
  for (int j = 0; j < human::kNumJoints; ++j) {
    const auto joint = static_cast<human::Joint>(j);
    const core::Pose& X = X_WJ[static_cast<size_t>(j)];
    worldbody += fmt::format(R"(<body name="human_{}" mocap="true" pos="{}" quat="{}">)",
                             human::joint_name(joint), vec(X.translation), quat(X.rotation));
    worldbody += "\n";
    for (const human::BodyCapsule& c : capsules) {
      if (c.joint != joint) continue;
      // The hand's contact capsule is not drawn (group 3): the drawn hand shows it (below).
      worldbody += fmt::format(
          R"(<geom name="human_{}" class="human" type="capsule" fromto="{} {}" size="{}" rgba="{}"{}/>)",
          c.name, vec(c.from), vec(c.to), num(c.radius), region_rgba(c.region),
          c.region == human::BodyRegion::kHand ? R"( group="3")" : "");
      worldbody += "\n";
    }
    for (const human::Side side : {human::Side::kLeft, human::Side::kRight}) {
      if (joint != human::wrist(side)) continue;
      const core::Pose& P = X_wrist_palm[static_cast<size_t>(side)];
      worldbody += fmt::format(
          R"(<site name="palm_{}" pos="{}" quat="{}" size="0.01" rgba="1 0 1 0"/>)",
          human::to_string(side), vec(P.translation), quat(P.rotation));
      worldbody += "\n";
    }
    worldbody += "</body>\n";
  }
  // The drawn hands (human/hand.h): one mocap body per part, after every other body so that
  // the ids of the bodies and geoms that take part in the physics do not depend on them.
  const auto X_W = human::hand_part_poses(skeleton, pose, X_WJ);
  const auto capsules_of_hand = human::hand_capsules(skeleton);
  for (const human::Side side : {human::Side::kLeft, human::Side::kRight}) {
    const size_t h = side == human::Side::kLeft ? 0 : 1;
    for (int p = 0; p < human::kNumHandParts; ++p) {
      const auto part = static_cast<human::HandPart>(p);
      const core::Pose& X = X_W[h][static_cast<size_t>(p)];
      worldbody += fmt::format(R"(<body name="{}" mocap="true" pos="{}" quat="{}">)",
                               human_hand_part_body(side, part), vec(X.translation), quat(X.rotation));
      worldbody += "\n";
      for (const human::HandCapsule& c : capsules_of_hand) {
        if (c.part != part) continue;
        worldbody += fmt::format(
            R"(<geom type="capsule" fromto="{} {}" size="{}" rgba="{}" group="{}" contype="0" conaffinity="0"/>)",
            vec(c.from), vec(c.to), num(c.radius), region_rgba(human::BodyRegion::kHand),
            kDrawnHandGroup);
        worldbody += "\n";
      }
      worldbody += "</body>\n";
    }
  }
}

std::string human_hand_part_body(human::Side side, human::HandPart part) {
  return fmt::format("human_{}_{}", human::to_string(side), human::to_string(part));
}

}  // namespace hribench::model::mjcf
