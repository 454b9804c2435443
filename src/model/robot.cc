// Robot descriptions: joint vectors, the registry of descriptions by name, and a description's
// MJCF (a <body> chain, its gripper tendon/equality and its servos).

#include "model/robot.h"

#include <algorithm>
#include <string>

#include <fmt/format.h>

#include "core/errors.h"
#include "model/mjcf.h"

namespace hribench::model {

JointVector::JointVector(size_t n, double value) : size_(n) {
  HRIB_CHECK(n <= kMaxArmDof) << n << " joints exceed JointVector's capacity " << kMaxArmDof;
  std::fill_n(values_.begin(), n, value);
}

JointVector::JointVector(std::initializer_list<double> values) : size_(values.size()) {
  HRIB_CHECK(values.size() <= kMaxArmDof)
      << values.size() << " joints exceed JointVector's capacity " << kMaxArmDof;
  std::copy(values.begin(), values.end(), values_.begin());
}

bool JointVector::operator==(const JointVector& other) const {
  return size_ == other.size_ && std::equal(begin(), end(), other.begin());
}

namespace {

JointVector per_joint(const Robot& robot, double ArmJoint::*field) {
  JointVector v(robot.dof());
  for (size_t i = 0; i < robot.dof(); ++i) v[i] = robot.joints[i].*field;
  return v;
}

}  // namespace

JointVector Robot::q_min() const { return per_joint(*this, &ArmJoint::q_min); }
JointVector Robot::q_max() const { return per_joint(*this, &ArmJoint::q_max); }
JointVector Robot::home() const { return per_joint(*this, &ArmJoint::home); }

const std::vector<std::string_view>& robot_names() {
  static const std::vector<std::string_view> names = {panda().name};
  return names;
}

const Robot& robot_by_name(std::string_view name) {
  if (name == panda().name) return panda();
  std::string known;
  for (const std::string_view n : robot_names()) known += (known.empty() ? "" : ", ") + std::string(n);
  throw core::InputError("robot", "one of " + known, "'" + std::string(name) + "'");
}

namespace mjcf {
namespace {

// One finger body; side = +1 (left, moves along +y of the hand) or -1 (right).
void finger(const ParallelGripper& g, int side, std::string& out) {
  const double sy = side;
  const std::string name = side > 0 ? "left_finger" : "right_finger";
  const std::string joint = side > 0 ? "finger_joint1" : "finger_joint2";
  out += fmt::format(R"(<body name="{}" pos="0 0 {}">)", name, num(g.finger_z)) + "\n";
  out += fmt::format(
      R"(<joint name="{}" type="slide" axis="0 {} 0" range="0 {}" armature="{}" damping="{}"/>)",
      joint, num(sy), num(g.finger_travel), num(g.finger_armature), num(g.finger_damping));
  out += "\n";
  Shape body = g.finger_shape;
  body.a.y() *= sy;
  shape_geoms({body}, g.finger_mass, name, g.finger_class, out);
  out += fmt::format(R"(<geom name="{}_pad" class="{}" type="box" pos="{}" size="{}" mass="{}"/>)",
                     name, g.pad_class, vec(core::Vec3(g.pad_centre.x(), sy * g.pad_centre.y(), g.pad_centre.z())),
                     vec(g.pad_half), num(g.pad_mass));
  out += "\n</body>\n";
}

}  // namespace

void robot(const Robot& r, const core::Vec3& base, std::string& defaults, std::string& worldbody,
           std::string& tendon, std::string& equality, std::string& actuator) {
  const int robot_aff = kBitStatic | kBitObject | kBitHuman;
  defaults += fmt::format(R"(<default class="{}"><geom contype="{}" conaffinity="{}" {}/>)",
                          r.root.name, kBitRobot, robot_aff, r.root.geom) + "\n";
  for (const GeomClass& c : r.classes)
    defaults += fmt::format(R"(  <default class="{}"><geom {}/></default>)", c.name, c.geom) + "\n";
  defaults += "</default>\n";

  // The link chain: each link's body nested in its parent's, its joint first.
  const Link& base_link = r.links.front();
  worldbody += fmt::format(R"(<body name="{}" childclass="{}" pos="{}">)", base_link.name,
                           r.root.name, vec(base)) + "\n";
  shape_geoms(base_link.shapes, base_link.mass, base_link.name, base_link.geom_class, worldbody);
  for (size_t i = 0; i < r.joints.size(); ++i) {
    const ArmJoint& j = r.joints[i];
    const Link& link = r.links[i + 1];
    worldbody += fmt::format(R"(<body name="{}" pos="{}" quat="{}">)", link.name, vec(link.pos),
                             quat(link.quat)) + "\n";
    worldbody += fmt::format(
        R"(<joint name="{}" type="hinge" axis="{}" range="{} {}" armature="{}" damping="{}"/>)",
        j.name, vec(j.axis), num(j.q_min), num(j.q_max), num(j.armature), num(j.damping)) + "\n";
    shape_geoms(link.shapes, link.mass, link.name, link.geom_class, worldbody);
  }
  // Flange, hand, TCP, wrist camera, fingers.
  const ParallelGripper& g = r.gripper;
  worldbody += fmt::format(R"(<site name="flange" pos="{}" size="0.005" rgba="1 0 0 0"/>)",
                           vec(r.flange)) + "\n";
  worldbody += fmt::format(R"(<body name="hand" pos="{}" quat="{}">)", vec(r.flange),
                           quat(g.hand_quat)) + "\n";
  shape_geoms(g.hand_shapes, g.hand_mass, "hand", r.root.name, worldbody);
  worldbody += fmt::format(R"(<site name="tcp" pos="0 0 {}" size="0.005" rgba="0 1 0 0"/>)",
                           num(g.tcp_offset)) + "\n";
  const HandCamera& cam = r.wrist_camera;
  worldbody += fmt::format(R"(<camera name="{}" pos="{}" xyaxes="{}" fovy="{}"/>)", cam.name,
                           vec(cam.pos), camera_xyaxes(cam.pos, cam.target, cam.up), num(cam.fovy)) + "\n";
  finger(g, +1, worldbody);
  finger(g, -1, worldbody);
  worldbody += "</body>\n";  // hand
  for (size_t i = 0; i < r.joints.size(); ++i) worldbody += "</body>\n";
  worldbody += "</body>\n";  // base link

  // Gripper: one servo on the opening width (q1 + q2), fingers coupled by an equality.
  tendon += R"(<fixed name="gripper_width"><joint joint="finger_joint1" coef="1"/><joint joint="finger_joint2" coef="1"/></fixed>)";
  tendon += "\n";
  equality += R"(<joint name="finger_coupling" joint1="finger_joint1" joint2="finger_joint2" polycoef="0 1 0 0 0" solref="0.005 1"/>)";
  equality += "\n";
  for (const ArmJoint& j : r.joints) {
    actuator += fmt::format(
        R"(<general name="{}" joint="{}" ctrllimited="true" ctrlrange="{} {}" forcelimited="true" forcerange="{} {}" gaintype="fixed" biastype="affine" gainprm="{}" biasprm="0 {} {}"/>)",
        j.actuator, j.name, num(j.q_min), num(j.q_max), num(-j.tau_max), num(j.tau_max),
        num(j.kp), num(-j.kp), num(-j.kv)) + "\n";
  }
  actuator += fmt::format(
      R"(<general name="gripper" tendon="gripper_width" ctrllimited="true" ctrlrange="0 {}" forcelimited="true" forcerange="{} {}" gaintype="fixed" biastype="affine" gainprm="{}" biasprm="0 {} {}"/>)",
      num(g.max_width()), num(-g.force_max), num(g.force_max), num(g.kp), num(-g.kp),
      num(-g.kv)) + "\n";
}

}  // namespace mjcf
}  // namespace hribench::model
