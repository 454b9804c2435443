// The Franka Emika Panda with the Franka Hand, written from reference/robots.md: modified-DH
// link frames, joint/torque limits, link masses (inertias from the primitive geometry), and
// primitive collision geometry approximating the real links.

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "model/mjcf.h"

namespace hribench::model::mjcf {
namespace {

using core::Vec3;

// Link masses (kg): link0..link7 (Gaz et al. identification, robots.md), hand, one finger.
constexpr std::array<double, 8> kLinkMass = {0.629769, 4.970684, 0.646926, 3.228604,
                                             3.587895, 1.225946, 1.666555, 0.735522};
constexpr double kHandMass = 0.73;
constexpr double kFingerMass = 0.015;
// Position-servo gains (menagerie): kp per joint, kv = kp / 10.
constexpr std::array<double, kArmDof> kKp = {4500, 4500, 3500, 3500, 2000, 2000, 2000};
// Gripper servo on the width tendon (q1 + q2): N/m and N s/m.
constexpr double kGripperKp = 1000;
constexpr double kGripperKv = 40;


// Collision geometry of each link in its own (DH) frame.
std::vector<Shape> link_shapes(int link) {
  switch (link) {
    case 0:
      return {cylinder(Vec3(-0.02, 0, 0), Vec3(-0.02, 0, 0.15), 0.09)};
    case 1:
      return {capsule(Vec3(0, 0, -0.18), Vec3(0, 0, -0.06), 0.065),
              capsule(Vec3(0, -0.05, 0), Vec3(0, 0.05, 0), 0.065)};
    case 2:
      return {capsule(Vec3(0, 0, -0.06), Vec3(0, 0, 0.06), 0.06),
              capsule(Vec3(0, 0, 0), Vec3(0, -0.14, 0), 0.06)};
    case 3:
      return {capsule(Vec3(0, 0, -0.2), Vec3(0, 0, 0), 0.06),
              capsule(Vec3(0, 0, 0), Vec3(0.0825, 0, 0), 0.055)};
    case 4:
      return {capsule(Vec3(0, 0, -0.055), Vec3(0, 0, 0.055), 0.06),
              capsule(Vec3(0, 0, 0), Vec3(-0.0825, 0.12, 0), 0.055)};
    case 5:
      return {capsule(Vec3(0, 0, -0.25), Vec3(0, 0, -0.02), 0.055),
              capsule(Vec3(0, 0.07, -0.22), Vec3(0, 0.07, -0.1), 0.03)};
    case 6:
      return {capsule(Vec3(0, 0, -0.06), Vec3(0, 0, 0.02), 0.06),
              capsule(Vec3(0, 0, 0), Vec3(0.088, 0, 0), 0.05)};
    default:
      return {capsule(Vec3(0, 0, -0.01), Vec3(0, 0, 0.065), 0.05)};
  }
}

// One finger body; side = +1 (left, moves along +y of the hand) or -1 (right).
void finger(int side, std::string& out) {
  const double sy = side;
  const std::string name = side > 0 ? "left_finger" : "right_finger";
  const std::string joint = side > 0 ? "finger_joint1" : "finger_joint2";
  out += fmt::format(R"(<body name="{}" pos="0 0 0.0584">)", name) + "\n";
  out += fmt::format(
      R"(<joint name="{}" type="slide" axis="0 {} 0" range="0 {}" armature="0.01" damping="2"/>)",
      joint, num(sy), num(kFingerMax));
  out += "\n";
  // Finger structure (behind the pad) and the high-friction pad on the inner face near the tip.
  std::vector<Shape> body = {box(Vec3(0, sy * 0.009, 0.027), Vec3(0.01, 0.005, 0.027))};
  shape_geoms(body, kFingerMass * 0.8, name, "panda_finger", out);
  out += fmt::format(
      R"(<geom name="{}_pad" class="panda_pad" type="box" pos="{}" size="0.0095 0.002 0.0135" mass="{}"/>)",
      name, vec(Vec3(0, sy * 0.002, 0.041)), num(kFingerMass * 0.2));
  out += "\n</body>\n";
}

}  // namespace

void panda(std::string& defaults, std::string& worldbody, std::string& tendon,
           std::string& equality, std::string& actuator) {
  const int robot_aff = kBitStatic | kBitObject | kBitHuman;
  defaults += fmt::format(
      R"(<default class="panda"><geom contype="{0}" conaffinity="{1}" condim="3" friction="0.8 0.005 0.0001" rgba="0.92 0.92 0.95 1"/>
  <default class="panda_dark"><geom rgba="0.25 0.25 0.28 1"/></default>
  <default class="panda_finger"><geom condim="4" friction="1.0 0.01 0.0001" rgba="0.25 0.25 0.28 1"/></default>
  <default class="panda_pad"><geom condim="4" friction="1.6 0.02 0.0001" solref="0.005 1" solimp="0.95 0.99 0.001" rgba="0.1 0.1 0.1 1"/></default>
</default>
)",
      kBitRobot, robot_aff);

  // Link frames by modified DH: T_{i-1,i} = RotX(alpha_{i-1}) TransX(a_{i-1}) RotZ(q_i)
  // TransZ(d_i), i.e. body pos = (a, -d sin(alpha), d cos(alpha)), quat = RotX(alpha).
  worldbody += "<body name=\"link0\" childclass=\"panda\" pos=\"0 0 " + num(kTableTopZ) + "\">\n";
  shape_geoms(link_shapes(0), kLinkMass[0], "link0", "panda", worldbody);
  for (int i = 1; i <= kArmDof; ++i) {
    const DhRow& dh = kPandaDh[i - 1];
    const Vec3 pos(dh.a, -dh.d * std::sin(dh.alpha), dh.d * std::cos(dh.alpha));
    const core::Quat q = core::axis_angle(Vec3::UnitX(), dh.alpha);
    worldbody += fmt::format(R"(<body name="link{}" pos="{}" quat="{}">)", i, vec(pos), quat(q));
    worldbody += "\n";
    worldbody += fmt::format(
        R"(<joint name="panda_joint{}" type="hinge" axis="0 0 1" range="{} {}" armature="0.1" damping="1"/>)",
        i, num(kArmQMin[static_cast<size_t>(i - 1)]), num(kArmQMax[static_cast<size_t>(i - 1)]));
    worldbody += "\n";
    shape_geoms(link_shapes(i), kLinkMass[static_cast<size_t>(i)], fmt::format("link{}", i),
          i == 7 ? "panda_dark" : "panda", worldbody);
  }
  // Flange, hand (rotated -45 deg about z), TCP, wrist camera, fingers.
  worldbody += fmt::format(R"(<site name="flange" pos="0 0 {}" size="0.005" rgba="1 0 0 0"/>)",
                           num(kFlangeLength));
  worldbody += "\n";
  worldbody += fmt::format(R"(<body name="hand" pos="0 0 {}" quat="{}">)", num(kFlangeLength),
                           quat(core::axis_angle(Vec3::UnitZ(), -core::kPi / 4)));
  worldbody += "\n";
  shape_geoms({box(Vec3(0, 0, 0.035), Vec3(0.03, 0.1, 0.024)),
         cylinder(Vec3(0, 0, 0), Vec3(0, 0, 0.012), 0.045)},
        kHandMass, "hand", "panda", worldbody);
  worldbody += fmt::format(R"(<site name="tcp" pos="0 0 {}" size="0.005" rgba="0 1 0 0"/>)",
                           num(kTcpOffset));
  worldbody += "\n";
  // Wrist camera: beside the hand housing (+x side), looking along the fingers; image up is
  // the hand's +x, so the fingers appear in the lower half of the image.
  const Vec3 cam_pos(0.05, 0, 0.05);
  worldbody += fmt::format(R"(<camera name="wrist" pos="{}" xyaxes="{}" fovy="75"/>)",
                           vec(cam_pos), camera_xyaxes(cam_pos, Vec3(0, 0, 0.2), Vec3::UnitX()));
  worldbody += "\n";
  finger(+1, worldbody);
  finger(-1, worldbody);
  worldbody += "</body>\n";  // hand
  for (int i = 1; i <= kArmDof; ++i) worldbody += "</body>\n";
  worldbody += "</body>\n";  // link0

  // Gripper: one servo on the opening width (q1 + q2), fingers coupled by an equality.
  tendon += R"(<fixed name="gripper_width"><joint joint="finger_joint1" coef="1"/><joint joint="finger_joint2" coef="1"/></fixed>)";
  tendon += "\n";
  equality += R"(<joint name="finger_coupling" joint1="finger_joint1" joint2="finger_joint2" polycoef="0 1 0 0 0" solref="0.005 1"/>)";
  equality += "\n";
  for (size_t i = 0; i < kKp.size(); ++i) {
    actuator += fmt::format(
        R"(<general name="actuator{}" joint="panda_joint{}" ctrllimited="true" ctrlrange="{} {}" forcelimited="true" forcerange="{} {}" gaintype="fixed" biastype="affine" gainprm="{}" biasprm="0 {} {}"/>)",
        i + 1, i + 1, num(kArmQMin[i]), num(kArmQMax[i]), num(-kArmTauMax[i]), num(kArmTauMax[i]),
        num(kKp[i]), num(-kKp[i]), num(-kKp[i] / 10));
    actuator += "\n";
  }
  actuator += fmt::format(
      R"(<general name="gripper" tendon="gripper_width" ctrllimited="true" ctrlrange="0 {}" forcelimited="true" forcerange="{} {}" gaintype="fixed" biastype="affine" gainprm="{}" biasprm="0 {} {}"/>)",
      num(kGripperMaxWidth), num(-kGripperForceMax), num(kGripperForceMax), num(kGripperKp),
      num(-kGripperKp), num(-kGripperKv));
  actuator += "\n";
}

}  // namespace hribench::model::mjcf
