// The kinematic human: one mocap body per skeleton joint, carrying that joint's capsules.

#include <string>
#include <vector>

#include <fmt/format.h>

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
      // The hand's contact capsule is not drawn (group 3): renderers draw the hand's fingers in
      // its place (render/renderer.h, human/hand.h).
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
}

}  // namespace hribench::model::mjcf
