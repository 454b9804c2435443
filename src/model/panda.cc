// The Franka Emika Panda with the Franka Hand as a robot description (model/robot.h), written
// from docs/robots.md: modified-DH link frames, joint/velocity/torque limits, link masses
// (inertias from the primitive geometry), menagerie's servo gains and home pose, and primitive
// collision geometry approximating the real links.

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "model/robot.h"

namespace hribench::model {
namespace {

using core::Vec3;

// Modified DH (Craig) of docs/robots.md: a_{i-1} (m), d_i (m), alpha_{i-1} (rad) for joints
// 1..7; the flange is d = 0.107 m along z7.
struct DhRow {
  double a, d, alpha;
};
constexpr std::array<DhRow, 7> kDh = {{{0, 0.333, 0},
                                        {0, 0, -core::kPi / 2},
                                        {0, 0.316, core::kPi / 2},
                                        {0.0825, 0, core::kPi / 2},
                                        {-0.0825, 0.384, -core::kPi / 2},
                                        {0, 0, core::kPi / 2},
                                        {0.088, 0, core::kPi / 2}}};
constexpr double kFlangeLength = 0.107;

// Joint limits (position, velocity, torque) and the home keyframe (docs/robots.md).
constexpr std::array<double, 7> kQMin = {-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973};
constexpr std::array<double, 7> kQMax = {2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973};
constexpr std::array<double, 7> kQdMax = {2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61};
constexpr std::array<double, 7> kTauMax = {87, 87, 87, 87, 12, 12, 12};
constexpr std::array<double, 7> kHome = {0, 0, 0, -1.57079, 0, 1.57079, -0.7853};
// Position-servo gains (menagerie): kp per joint, kv = kp / 10.
constexpr std::array<double, 7> kKp = {4500, 4500, 3500, 3500, 2000, 2000, 2000};
// Link masses (kg): link0..link7 (Gaz et al. identification), hand, one finger.
constexpr std::array<double, 8> kLinkMass = {0.629769, 4.970684, 0.646926, 3.228604,
                                             3.587895, 1.225946, 1.666555, 0.735522};
constexpr double kHandMass = 0.73;
constexpr double kFingerMass = 0.015;

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

Robot make_panda() {
  Robot r;
  r.name = "panda";
  r.root = {"panda", R"(condim="3" friction="0.8 0.005 0.0001" rgba="0.92 0.92 0.95 1")"};
  r.classes = {
      {"panda_dark", R"(rgba="0.25 0.25 0.28 1")"},
      {"panda_finger", R"(condim="4" friction="1.0 0.01 0.0001" rgba="0.25 0.25 0.28 1")"},
      {"panda_pad",
       R"(condim="4" friction="1.6 0.02 0.0001" solref="0.005 1" solimp="0.95 0.99 0.001" rgba="0.1 0.1 0.1 1")"}};
  r.links.push_back({"link0", Vec3::Zero(), core::Quat::Identity(), kLinkMass[0], link_shapes(0), "panda"});
  for (size_t i = 0; i < kDh.size(); ++i) {
    ArmJoint j;
    j.name = fmt::format("panda_joint{}", i + 1);
    j.actuator = fmt::format("actuator{}", i + 1);
    j.q_min = kQMin[i];
    j.q_max = kQMax[i];
    j.qd_max = kQdMax[i];
    j.tau_max = kTauMax[i];
    j.kp = kKp[i];
    j.kv = kKp[i] / 10;
    j.armature = 0.1;
    j.damping = 1;
    j.home = kHome[i];
    r.joints.push_back(j);
    // Link frames by modified DH: T_{i-1,i} = RotX(alpha_{i-1}) TransX(a_{i-1}) RotZ(q_i)
    // TransZ(d_i), i.e. body pos = (a, -d sin(alpha), d cos(alpha)), quat = RotX(alpha).
    const DhRow& dh = kDh[i];
    const int link = static_cast<int>(i) + 1;
    r.links.push_back({fmt::format("link{}", link),
                       Vec3(dh.a, -dh.d * std::sin(dh.alpha), dh.d * std::cos(dh.alpha)),
                       core::axis_angle(Vec3::UnitX(), dh.alpha), kLinkMass[i + 1],
                       link_shapes(link), link == 7 ? "panda_dark" : "panda"});
  }
  r.flange = Vec3(0, 0, kFlangeLength);

  // The Franka Hand, mounted rotated -45 deg about the flange z; TCP 0.1034 m along z_hand;
  // fingers 0..0.04 m each from 0.0584 m along z_hand.
  ParallelGripper& g = r.gripper;
  g.hand_quat = core::axis_angle(Vec3::UnitZ(), -core::kPi / 4);
  g.hand_mass = kHandMass;
  g.hand_shapes = {box(Vec3(0, 0, 0.035), Vec3(0.03, 0.1, 0.024)),
                   cylinder(Vec3(0, 0, 0), Vec3(0, 0, 0.012), 0.045)};
  g.tcp_offset = 0.1034;
  g.finger_travel = 0.04;
  g.finger_z = 0.0584;
  // The fingers' reflected drive inertia (kg). The gripper servo's damping (kv 40 N·s/m on the
  // opening, 80 per finger) is taken explicitly by the Euler integrator: each step multiplies a
  // finger's velocity by 1 - h·80/m, which must stay within (-1, 1) (0.01 and 0.05 kg did not at
  // 2.5 ms: the fingers buzzed in place short of their target). At the 5 ms step (pool v7)
  // 1.2 kg gives 0.67, where 0.1 kg would give -3 and 0.3 kg -0.33 (a held bottle flickered in
  // and out of the grasp). Damping the fingers in their joints instead softened their contacts
  // (a held cube squeezed to 31-49 mm of its 50): docs/performance.md, "Physics".
  g.finger_armature = 1.2;
  g.finger_damping = 2;
  // Finger structure (behind the pad) and the high-friction pad on the inner face near the tip.
  g.finger_shape = box(Vec3(0, 0.009, 0.027), Vec3(0.01, 0.005, 0.027));
  g.finger_mass = kFingerMass * 0.8;
  g.pad_centre = Vec3(0, 0.002, 0.041);
  g.pad_half = Vec3(0.0095, 0.002, 0.0135);
  g.pad_mass = kFingerMass * 0.2;
  g.finger_class = "panda_finger";
  g.pad_class = "panda_pad";
  // Width servo: force-limited so closing on an object squeezes it with at most 70 N.
  g.force_max = 70;
  g.kp = 1000;
  g.kv = 40;

  // Wrist camera: beside the hand housing (+x side), looking along the fingers; image up is
  // the hand's +x, so the fingers appear in the lower half of the image.
  r.wrist_camera = {"wrist", Vec3(0.05, 0, 0.05), Vec3(0, 0, 0.2), Vec3::UnitX(), 75};
  return r;
}

}  // namespace

const Robot& panda() {
  static const Robot robot = make_panda();
  return robot;
}

}  // namespace hribench::model
