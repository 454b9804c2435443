#include "sim/data.h"

#include <sstream>

#include "core/errors.h"
#include "sim/hold.h"
#include "sim/memory.h"

namespace hribench::sim {

namespace {
constexpr int kScratchStack = 1000;  // mjtNum: mj_makeData wants some stack, the scratch uses none
}  // namespace

Data make_data(const model::Model& model) {
  const mjModel* m = model.m();
  HRIB_CHECK(m != nullptr) << "make_data on an unbuilt Model";
  keep_large_allocations();  // the state's buffer and stack on memory a previous scene mapped
  Data data;
  data.mj.reset(mj_makeData(m));
  // The IK scratch runs only kinematics, centres of mass and Jacobians (sim/control.cc), which
  // touch no constraint row, contact or stack slot, so it is made without the constraint arena
  // (about 12 MB that MuJoCo clears per mjData: docs/performance.md, "Fixed costs per episode"):
  // mj_makeData reads the sizes from the struct, and the shallow copy shares every array of `m`.
  // A stack use would stop with MuJoCo's stack error, never go unseen.
  mjModel scratch_sizes = *m;
  scratch_sizes.njmax = 0;
  scratch_sizes.nconmax = 0;
  scratch_sizes.nstack = kScratchStack;
  data.scratch.reset(mj_makeData(&scratch_sizes));
  HRIB_CHECK(data.mj && data.scratch) << "mj_makeData failed";
  data.jacobian.assign(static_cast<size_t>(6 * m->nv), 0.0);
  reset(model, data);
  return data;
}

void copy_data(const model::Model& model, const Data& from, Data& to) {
  HRIB_CHECK(from.mj && to.mj) << "copy_data between Data made by make_data";
  mj_copyData(to.mj.get(), model.m(), from.mj.get());
  to.q_target = from.q_target;
  to.gripper_width_target = from.gripper_width_target;
  to.human_pose = from.human_pose;
  to.X_WJ = from.X_WJ;
  to.human_pose_dirty = from.human_pose_dirty;
  to.hold = from.hold;
}

void reset(const model::Model& model, Data& data) {
  reset(model, data, model.has_human ? model.human_start : human::SkeletonPose());
}

void reset(const model::Model& model, Data& data, const human::SkeletonPose& human_start) {
  const mjModel* m = model.m();
  mjData* d = data.mj.get();
  // Home keyframe: robot home, fingers open, objects at their spec poses, human at start.
  mj_resetDataKeyframe(m, d, 0);
  data.q_target = model.robot.home();
  data.gripper_width_target = model.robot.gripper.max_width();
  for (size_t i = 0; i < data.q_target.size(); ++i) d->ctrl[model.arm_actuator[i]] = data.q_target[i];
  d->ctrl[model.gripper_actuator] = data.gripper_width_target;
  data.hold = {};
  data.human_pose = human_start;
  data.human_pose_dirty = true;
  pose_human(model, data);
  // Objects that start in a hand: placed at the palm of the start pose, and held.
  for (size_t i = 0; i < model.objects.size(); ++i) {
    const model::ObjectInfo& o = model.objects[i];
    if (!o.held_by || !model.has_human) continue;
    const core::Pose X_WO = palm_pose(model, data, *o.held_by) * o.X_palm_hold;
    mjtNum* q = d->qpos + o.qpos_adr;
    q[0] = X_WO.translation.x();
    q[1] = X_WO.translation.y();
    q[2] = X_WO.translation.z();
    core::quat_to_wxyz(X_WO.rotation, q + 3);
    grasp_by_human(model, data, *o.held_by, static_cast<int>(i), o.X_palm_hold);
  }
  mj_forward(m, d);
}

void set_human_pose(const model::Model& model, Data& data, const human::SkeletonPose& pose) {
  if (!model.has_human) return;
  data.human_pose = pose;
  data.human_pose_dirty = true;
}

void pose_human(const model::Model& model, Data& data) {
  if (!model.has_human || !data.human_pose_dirty) return;
  data.X_WJ = human::forward_kinematics(model.skeleton, data.human_pose);
  mjData* d = data.mj.get();
  for (size_t j = 0; j < human::kNumJoints; ++j) {
    const int mocap = model.human_mocap[j];
    const core::Pose& X = data.X_WJ[j];
    mjtNum* pos = d->mocap_pos + 3 * mocap;
    pos[0] = X.translation.x();
    pos[1] = X.translation.y();
    pos[2] = X.translation.z();
    core::quat_to_wxyz(X.rotation, d->mocap_quat + 4 * mocap);
  }
  // The hands' shapes, for the renderers (model::kHandShapeValues).
  static_assert(model::kHandShapeValues == 4);
  for (size_t h = 0; h < 2; ++h) {
    d->userdata[2 * h] = data.human_pose.hands[h].grip;
    d->userdata[2 * h + 1] = data.human_pose.hands[h].point;
  }
  data.human_pose_dirty = false;
}

namespace {

// The arm servos' velocity terms kv·q̇ that model::servo_damping_in_joints also put in the
// joints' damping, added back unclamped.
void add_back_servo_damping(const model::Model& model, mjData& d) {
  const mjModel& m = *model.m();
  for (size_t j = 0; j < model.arm_actuator.size(); ++j) {
    const int dof = model.arm_dof_adr[j];
    d.qfrc_applied[dof] += model::servo_kv(m, model.arm_actuator[j]) * d.qvel[dof];
  }
}

}  // namespace

void step(const model::Model& model, Data& data) {
  prepare_step(model, data);
  mj_step(model.m(), data.mj.get());
}

void prepare_step(const model::Model& model, Data& data) {
  mjData* d = data.mj.get();
  pose_human(model, data);
  apply_hold_wrenches(model, data);
  // Gravity (and Coriolis) compensation of the arm, as the Panda's own controller does; the
  // bias forces are those of the last forward pass (one step old).
  for (const int dof : model.arm_dof_adr) d->qfrc_applied[dof] = d->qfrc_bias[dof];
  if (model.servo_damping_in_joints) add_back_servo_damping(model, *d);
}

void forward(const model::Model& model, Data& data) {
  pose_human(model, data);
  mj_forward(model.m(), data.mj.get());
}

void observe_state(const model::Model& model, Data& data) {
  pose_human(model, data);
  const mjModel* m = model.m();
  mjData* d = data.mj.get();
  mj_kinematics(m, d);
  mj_comPos(m, d);
  mj_camlight(m, d);
  mj_comVel(m, d);
}

int warning_count(const Data& data) {
  int n = 0;
  for (int i = 0; i < mjNWARNING; ++i) n += data.mj->warning[i].number;
  return n;
}

std::string warning_summary(const Data& data) {
  std::ostringstream out;
  for (int i = 0; i < mjNWARNING; ++i) {
    const mjWarningStat& w = data.mj->warning[i];
    if (w.number == 0) continue;
    if (out.tellp() > 0) out << ", ";
    out << warning_name(i) << " x" << w.number << " (info " << w.lastinfo << ")";
  }
  return out.str();
}

}  // namespace hribench::sim
