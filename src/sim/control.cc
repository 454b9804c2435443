#include "sim/control.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "core/errors.h"

namespace hribench::sim {
namespace {

// Sized by the robot's dof at run time, stored in place (no allocation).
constexpr int kMaxDof = static_cast<int>(model::kMaxArmDof);
using Jacobian = Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::ColMajor, 6, kMaxDof>;
using JointColumn = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxDof, 1>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

// Joint targets stay this far inside the limits (rad), so the servo never fights a limit.
constexpr double kLimitMargin = 0.005;
// Joints closer than this to a limit (rad) are slowed down toward it by the IK weighting.
constexpr double kLimitZone = 0.3;
constexpr double kDamping = 1e-4;  // DLS lambda^2
constexpr int kIkIterations = 8;
constexpr double kMaxIterationStep = 0.4;  // rad per IK iteration

double clamp_joint(const model::ArmJoint& joint, double q) {
  return std::clamp(q, joint.q_min + kLimitMargin, joint.q_max - kLimitMargin);
}

// Scratch kinematics (poses of bodies, geoms and sites) for arm configuration q (other qpos as in
// the simulated state). A Jacobian needs scratch_com_pos after it.
void scratch_kinematics(const model::Model& model, Data& data, const ArmVector* q) {
  const mjModel* m = model.m();
  mjData* s = data.scratch.get();
  mju_copy(s->qpos, data.mj->qpos, m->nq);
  if (q != nullptr)
    for (size_t i = 0; i < q->size(); ++i) s->qpos[model.arm_qpos_adr[i]] = (*q)[i];
  mj_kinematics(m, s);
}

// The centres of mass and motion axes of the scratch kinematics (what mj_jacSite reads); they
// change no pose, so a pose read before or after is the same to the bit.
void scratch_com_pos(const model::Model& model, Data& data) { mj_comPos(model.m(), data.scratch.get()); }

core::Pose site_pose(const mjData* d, int site) {
  core::Pose X;
  X.translation = core::Vec3(d->site_xpos[3 * site], d->site_xpos[3 * site + 1],
                             d->site_xpos[3 * site + 2]);
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->site_xmat + 9 * site);
  X.rotation = core::Quat(core::Mat3(R)).normalized();
  return X;
}

core::Vec3 rotation_vector(const core::Quat& q) {
  const Eigen::AngleAxisd aa(q);
  return aa.axis() * aa.angle();
}

// The 6 x dof TCP Jacobian (linear; angular) of the scratch state.
Jacobian tcp_jacobian(const model::Model& model, Data& data) {
  const mjModel* m = model.m();
  mjtNum* jacp = data.jacobian.data();
  mjtNum* jacr = jacp + 3 * m->nv;
  scratch_com_pos(model, data);
  mj_jacSite(m, data.scratch.get(), jacp, jacr, model.tcp_site);
  Jacobian J(6, static_cast<Eigen::Index>(model.arm_dof_adr.size()));
  for (size_t c = 0; c < model.arm_dof_adr.size(); ++c) {
    const int dof = model.arm_dof_adr[c];
    for (int r = 0; r < 3; ++r) {
      J(r, static_cast<Eigen::Index>(c)) = jacp[r * m->nv + dof];
      J(r + 3, static_cast<Eigen::Index>(c)) = jacr[r * m->nv + dof];
    }
  }
  return J;
}

}  // namespace

void set_joint_targets(const model::Model& model, Data& data, const ArmVector& q) {
  HRIB_CHECK(q.size() == model.robot.dof())
      << "joint targets: " << q.size() << " values for " << model.robot.dof() << " joints";
  for (size_t i = 0; i < q.size(); ++i) {
    data.q_target[i] = clamp_joint(model.robot.joints[i], q[i]);
    data.mj->ctrl[model.arm_actuator[i]] = data.q_target[i];
  }
}

IkResult set_tcp_target(const model::Model& model, Data& data, const core::Pose& X_W_tcp) {
  IkResult result;
  ArmVector q = arm_joint_positions(model, data);
  const size_t dof = q.size();
  const auto n = static_cast<Eigen::Index>(dof);
  for (size_t i = 0; i < dof; ++i) q[i] = clamp_joint(model.robot.joints[i], q[i]);
  Vector6 e = Vector6::Zero();
  for (int iter = 0; iter <= kIkIterations; ++iter) {
    scratch_kinematics(model, data, &q);
    const core::Pose X = site_pose(data.scratch.get(), model.tcp_site);
    e.head<3>() = X_W_tcp.translation - X.translation;
    e.tail<3>() = rotation_vector(X_W_tcp.rotation * X.rotation.conjugate());
    if (iter == kIkIterations || (e.head<3>().norm() < 1e-6 && e.tail<3>().norm() < 1e-5)) break;
    const Jacobian J = tcp_jacobian(model, data);
    // Damped least squares, weighted: a joint near a limit moves less toward that limit.
    JointColumn weight = JointColumn::Ones(n);
    for (int pass = 0; pass < 2; ++pass) {
      const Jacobian JW = J * weight.asDiagonal();
      const Eigen::Matrix<double, 6, 6> A =
          JW * J.transpose() + kDamping * Eigen::Matrix<double, 6, 6>::Identity();
      JointColumn dq = weight.asDiagonal() * J.transpose() * A.ldlt().solve(e);
      if (pass == 0) {
        bool changed = false;
        for (size_t i = 0; i < dof; ++i) {
          const auto k = static_cast<Eigen::Index>(i);
          const model::ArmJoint& joint = model.robot.joints[i];
          const double room = dq(k) > 0 ? joint.q_max - q[i] : q[i] - joint.q_min;
          if (room < kLimitZone) {
            weight(k) = std::max(0.02, room / kLimitZone);
            changed = true;
          }
        }
        if (changed) continue;
      }
      const double largest = dq.cwiseAbs().maxCoeff();
      if (largest > kMaxIterationStep) dq *= kMaxIterationStep / largest;
      for (size_t i = 0; i < dof; ++i) {
        const double unclamped = q[i] + dq(static_cast<Eigen::Index>(i));
        q[i] = clamp_joint(model.robot.joints[i], unclamped);
        if (q[i] != unclamped) result.limited = true;
      }
      break;
    }
  }
  set_joint_targets(model, data, q);
  result.q_target = data.q_target;
  result.position_error = e.head<3>().norm();
  result.rotation_error = e.tail<3>().norm();
  return result;
}

IkResult apply_ee_delta(const model::Model& model, Data& data, const EeDelta& delta) {
  return apply_ee_delta(model, data, delta, tcp_pose(model, data));
}

IkResult apply_ee_delta(const model::Model& model, Data& data, const EeDelta& delta, const core::Pose& X) {
  core::Pose target;
  target.translation = X.translation + delta.translation;
  const double angle = delta.rotation.norm();
  const core::Quat dr =
      angle > 0 ? core::axis_angle(delta.rotation / angle, angle) : core::Quat::Identity();
  target.rotation = (dr * X.rotation).normalized();
  return set_tcp_target(model, data, target);
}

void set_gripper_width(const model::Model& model, Data& data, double width) {
  data.gripper_width_target = std::clamp(width, 0.0, model.robot.gripper.max_width());
  data.mj->ctrl[model.gripper_actuator] = data.gripper_width_target;
}

ArmVector arm_joint_positions(const model::Model& model, const Data& data) {
  ArmVector q(model.arm_qpos_adr.size());
  for (size_t i = 0; i < q.size(); ++i) q[i] = data.mj->qpos[model.arm_qpos_adr[i]];
  return q;
}

ArmVector arm_joint_velocities(const model::Model& model, const Data& data) {
  ArmVector v(model.arm_dof_adr.size());
  for (size_t i = 0; i < v.size(); ++i) v[i] = data.mj->qvel[model.arm_dof_adr[i]];
  return v;
}

double gripper_width(const model::Model& model, const Data& data) {
  return data.mj->qpos[model.finger_qpos_adr[0]] + data.mj->qpos[model.finger_qpos_adr[1]];
}

core::Pose tcp_pose(const model::Model& model, Data& data) {
  scratch_kinematics(model, data, nullptr);
  return site_pose(data.scratch.get(), model.tcp_site);
}

core::Pose observed_tcp_pose(const model::Model& model, const Data& data) {
  return site_pose(data.mj.get(), model.tcp_site);
}

core::Pose flange_pose(const model::Model& model, Data& data) {
  scratch_kinematics(model, data, nullptr);
  return site_pose(data.scratch.get(), model.flange_site);
}

double tcp_speed(const model::Model& model, Data& data) {
  const mjModel* m = model.m();
  scratch_kinematics(model, data, nullptr);
  scratch_com_pos(model, data);
  mjtNum* jacp = data.jacobian.data();
  mj_jacSite(m, data.scratch.get(), jacp, nullptr, model.tcp_site);
  core::Vec3 v = core::Vec3::Zero();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < m->nv; ++c) v[r] += jacp[r * m->nv + c] * data.mj->qvel[c];
  return v.norm();
}

}  // namespace hribench::sim
