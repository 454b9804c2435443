#pragma once
// Robot controllers and robot state queries.
//
// Everything robot-specific comes from the model's robot description (model/robot.h): the
// number of joints, their limits, the gripper's range. The arm has position servos (the
// description's kp, kv and torque limits) plus gravity compensation applied by step(), as the
// real Panda's controller does. Commands set servo targets; step() makes the physics follow.
//  - joint_pos: absolute joint targets (one per arm joint), clamped to the joint limits.
//  - ee_delta: a 6-D delta of the TCP pose, turned into joint targets by damped least-squares
//    differential IK (a few Gauss-Newton iterations on a scratch mjData) with joint-limit-aware
//    weighting and clamping.
//  - gripper: a target opening width (0 .. robot.gripper.max_width()) tracked by a
//    force-limited servo (robot.gripper.force_max); closing on an object squeezes it with up
//    to that force.
//
// Frames: W = world (core/math.h). The TCP frame is the hand frame translated
// robot.gripper.tcp_offset along the hand's z axis (pointing out between the fingers); its x
// axis is the hand x axis, y the finger motion axis.

#include "core/math.h"
#include "model/model.h"
#include "sim/data.h"

namespace hribench::sim {

// One value per arm joint, sized by the robot's dof (fixed capacity: allocation-free).
using ArmVector = model::JointVector;

// Clamps `q` (rad, model.robot.dof() values: HRIB_CHECK) into the joint limits and makes it the
// arm's servo target.
void set_joint_targets(const model::Model& model, Data& data, const ArmVector& q);

// A TCP pose delta: translation (m, world frame) and rotation vector (rad, world frame:
// droll, dpitch, dyaw about the world x, y, z axes, composed as one rotation vector, applied
// on the left: R_target = Exp(rotation) * R_current).
struct EeDelta {
  core::Vec3 translation = core::Vec3::Zero();
  core::Vec3 rotation = core::Vec3::Zero();
};

struct IkResult {
  ArmVector q_target{};          // the joint targets that were set (within limits)
  double position_error = 0;     // |p_target - p(q_target)|, m
  double rotation_error = 0;     // angle of R_target * R(q_target)^T, rad
  bool limited = false;          // a joint limit clamped the solution
};

// Sets joint targets that move the TCP from its current pose (from the current qpos) by
// `delta`. Allocation-free.
IkResult apply_ee_delta(const model::Model& model, Data& data, const EeDelta& delta);
// The same from a TCP pose the caller has (observed_tcp_pose of an observed state): no
// kinematics for the start pose.
IkResult apply_ee_delta(const model::Model& model, Data& data, const EeDelta& delta, const core::Pose& X_W_tcp);
// Same with the target TCP pose in world given directly.
IkResult set_tcp_target(const model::Model& model, Data& data, const core::Pose& X_W_tcp);

// Gripper target opening width, clamped to [0, model.robot.gripper.max_width()] m.
void set_gripper_width(const model::Model& model, Data& data, double width);
inline void open_gripper(const model::Model& model, Data& data) {
  set_gripper_width(model, data, model.robot.gripper.max_width());
}
inline void close_gripper(const model::Model& model, Data& data) {
  set_gripper_width(model, data, 0);
}

// Queries of the current state (from qpos: exact after any step or reset).
ArmVector arm_joint_positions(const model::Model& model, const Data& data);   // rad
ArmVector arm_joint_velocities(const model::Model& model, const Data& data);  // rad/s
double gripper_width(const model::Model& model, const Data& data);  // finger opening, m
// TCP / flange pose in world computed from the current qpos (uses data.scratch).
core::Pose tcp_pose(const model::Model& model, Data& data);
// The TCP pose in data's own kinematics, as the last sim::forward or sim::observe_state left
// them: tcp_pose's to the bit while qpos has not changed since (an episode observes its state
// after every control step), without computing the kinematics again (docs/performance.md).
core::Pose observed_tcp_pose(const model::Model& model, const Data& data);
core::Pose flange_pose(const model::Model& model, Data& data);
// TCP linear speed (m/s) from the current qpos/qvel.
double tcp_speed(const model::Model& model, Data& data);

}  // namespace hribench::sim
