#pragma once
// The robot as data: one description per robot (its joints and their limits, home pose, servo
// gains, gripper range, flange and TCP, link geometry and contact classes). Everything
// robot-specific is derived from it: the robot's MJCF (model.cc, robot_mjcf.cc), the joint
// vectors of sim and of the policy's proprioception (sized by dof()), the action dimensions and
// joint limits of policy/policy.h, the controllers' joint clamping (sim/control.h) and the
// gripper's range. No other file names a robot's joint count or limits
// (tests/model/robot_test.cc greps src/ for the Panda's).
//
// A robot is a serial chain of hinge joints from a base link, a flange on the last link, and a
// hand mounted at the flange carrying the TCP, a wrist camera and a two-finger parallel gripper
// (two slide joints, coupled, driven as one opening width). The Panda with the Franka Hand is
// panda() (panda.cc, from docs/robots.md's published values).
//
// Adding a robot (e.g. the SO-100):
//   1. write its description in src/model/<name>.cc (a function like panda()) and list it in
//      robot_by_name() (robot.cc); the MJCF, proprioception sizes, action dimensions and limits
//      follow from it;
//   2. give the oracle skills for it (src/policy/oracle*: the expert's grasp and offer geometry
//      is written for one hand; it refuses other robots);
//   3. name it in the episode (EpisodeSpec's robot, docs/robots.md).
// A gripper that is not two parallel slide fingers (the SO-100's jaw is a hinge) needs a second
// gripper kind here, its MJCF in robot_mjcf.cc and its opening in sim::gripper_width.

#include <array>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.h"
#include "script/scenario.h"

namespace hribench::model {

// The most arm joints any description may have (the capacity of JointVector).
inline constexpr size_t kMaxArmDof = 8;

// One value per arm joint (rad, rad/s, ...), sized by a robot's dof. A fixed capacity rather
// than a std::vector: the control loop copies joint vectors every control step (servo targets,
// IK, proprioception) and allocates nothing, and a vector is trivially copyable into Data
// snapshots.
class JointVector {
 public:
  JointVector() = default;
  // `n` values equal to `value`; n <= kMaxArmDof (HRIB_CHECK).
  explicit JointVector(size_t n, double value = 0);
  JointVector(std::initializer_list<double> values);

  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  double& operator[](size_t i) { return values_[i]; }
  double operator[](size_t i) const { return values_[i]; }
  double* data() { return values_.data(); }
  const double* data() const { return values_.data(); }
  double* begin() { return values_.data(); }
  double* end() { return values_.data() + size_; }
  const double* begin() const { return values_.data(); }
  const double* end() const { return values_.data() + size_; }
  // Equal sizes and bitwise-equal values (as ==).
  bool operator==(const JointVector& other) const;

 private:
  std::array<double, kMaxArmDof> values_{};
  size_t size_ = 0;
};

// Collision geometry primitive of a robot link or an object (in its body frame).
struct Shape {
  enum Kind { kCapsule, kBox, kCylinder } kind = kCapsule;
  core::Vec3 a = core::Vec3::Zero();  // capsule/cylinder: from; box: centre
  core::Vec3 b = core::Vec3::Zero();  // capsule/cylinder: to;   box: half sizes
  double radius = 0;
  double yaw = 0;  // box only: rotation about the body z axis (rad)
  double volume() const;
};

inline Shape capsule(const core::Vec3& a, const core::Vec3& b, double r) {
  return {Shape::kCapsule, a, b, r};
}
inline Shape box(const core::Vec3& centre, const core::Vec3& half) {
  return {Shape::kBox, centre, half, 0};
}
inline Shape cylinder(const core::Vec3& a, const core::Vec3& b, double r) {
  return {Shape::kCylinder, a, b, r};
}

// One arm joint: a hinge moving the link of the same index + 1 (joint i moves links[i + 1]),
// driven by a position servo (ctrl = target angle) with a torque limit.
struct ArmJoint {
  std::string name;      // MuJoCo joint name
  std::string actuator;  // MuJoCo actuator name of its servo, e.g. "actuator1"
  core::Vec3 axis = core::Vec3::UnitZ();  // hinge axis in its link's frame
  double q_min = 0;      // position limits, rad
  double q_max = 0;
  double qd_max = 0;     // velocity limit, rad/s (published; the simulation does not enforce it)
  double tau_max = 0;    // servo torque limit, N m
  double kp = 0;         // servo stiffness, N m / rad
  double kv = 0;         // servo damping, N m s / rad
  double armature = 0;   // reflected rotor inertia, kg m^2
  double damping = 0;    // joint viscous damping, N m s / rad
  double home = 0;       // home position, rad
};

// One rigid link: a MuJoCo body carrying its collision geometry.
struct Link {
  std::string name;  // MuJoCo body name, e.g. "link3"
  // Frame of the link in its parent link's frame (links[0], the base: in the robot base frame
  // B, so identity).
  core::Vec3 pos = core::Vec3::Zero();
  core::Quat quat = core::Quat::Identity();
  double mass = 0;                // kg, split over the shapes by volume
  std::vector<Shape> shapes;      // in the link frame
  std::string geom_class;         // the contact/appearance class of its geoms (Robot::classes)
};

// A contact/appearance class of robot geoms (an MJCF default class): `geom` holds the <geom>
// attributes (condim, friction, solref, rgba, ...).
struct GeomClass {
  std::string name;
  std::string geom;
};

// A two-finger parallel gripper on a hand body mounted at the flange. The fingers slide along
// the hand's y axis (left +y, right -y), coupled; one servo drives their opening width (the sum
// of both travels), force-limited, so closing on an object squeezes it with up to force_max.
struct ParallelGripper {
  core::Quat hand_quat = core::Quat::Identity();  // hand frame in the flange frame
  double hand_mass = 0;                           // kg
  std::vector<Shape> hand_shapes;                 // in the hand frame
  double tcp_offset = 0;     // hand frame -> TCP along z_hand, m
  double finger_travel = 0;  // each finger's stroke, m (opening 0 .. 2 * finger_travel)
  double finger_z = 0;       // finger joint origins along z_hand, m
  double finger_armature = 0;  // kg
  double finger_damping = 0;   // N s / m
  // The left finger's structure and pad in its frame (the right finger mirrors y), and their
  // masses (kg).
  Shape finger_shape;
  double finger_mass = 0;
  core::Vec3 pad_centre = core::Vec3::Zero();
  core::Vec3 pad_half = core::Vec3::Zero();
  double pad_mass = 0;
  std::string finger_class;  // GeomClass of the finger structure
  std::string pad_class;     // GeomClass of the pads
  double force_max = 0;      // N, width servo force limit
  double kp = 0;             // N / m on the width
  double kv = 0;             // N s / m on the width

  double max_width() const { return 2 * finger_travel; }  // full opening, m
};

// A camera on the hand (its frame), looking at `target` with image up toward `up`.
struct HandCamera {
  std::string name;
  core::Vec3 pos = core::Vec3::Zero();
  core::Vec3 target = core::Vec3::Zero();
  core::Vec3 up = core::Vec3::UnitZ();
  double fovy = 45;  // deg
};

struct Robot {
  std::string name;               // e.g. "panda"; recorded in every result
  std::vector<ArmJoint> joints;   // arm joints, base to tip
  std::vector<Link> links;        // links[0] = base (fixed); links[i + 1] moved by joints[i]
  core::Vec3 flange = core::Vec3::Zero();  // the flange in the last link's frame, m
  ParallelGripper gripper;
  HandCamera wrist_camera;
  // Contact classes: `root` is the class of every robot geom (its contact bits are added by
  // the scene), `classes` refine it (Link::geom_class, ParallelGripper::finger_class, ...).
  GeomClass root;
  std::vector<GeomClass> classes;

  size_t dof() const { return joints.size(); }
  JointVector q_min() const;   // rad
  JointVector q_max() const;   // rad
  JointVector home() const;    // rad
};

// The robot an episode uses when it names none.
inline constexpr std::string_view kDefaultRobot = script::kDefaultRobot;

// The Franka Emika Panda with the Franka Hand (panda.cc).
const Robot& panda();

// The description named `name`; throws core::InputError (where "robot") for an unknown name.
const Robot& robot_by_name(std::string_view name);
// Names robot_by_name knows, in a fixed order.
const std::vector<std::string_view>& robot_names();

}  // namespace hribench::model
