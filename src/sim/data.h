#pragma once
// The mutable state of one running episode (docs/design.md): MuJoCo's mjData plus the robot's
// controller targets, the human pose and the human's hold state. One Data per thread; the
// Model it was made from is shared read-only and must outlive it.
//
// Stepping: step() advances the world by one 200 Hz physics step (model::kTimestep = 5 ms):
// it poses the human mocap bodies from data.human_pose (forward kinematics only when the pose
// changed since the last step), applies the human hold wrenches and the robot's gravity
// compensation, then calls mj_step. It allocates nothing.
//
// Freshness: after step(), qpos/qvel/time are the new state, while MuJoCo's derived
// quantities (xpos, site_xpos, contacts, ...) are those of the previous state (mj_step
// computes them before integrating). Call forward() when you need them for the current state,
// observe_state() for its frames and velocities alone.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "core/math.h"
#include "human/skeleton.h"
#include "model/model.h"

namespace hribench::sim {

struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using MjDataPtr = std::unique_ptr<mjData, MjDataDeleter>;

// A human hand holding an object (see sim/hold.h).
struct HoldState {
  int object = -1;         // object index in Model::objects, or -1 when the hand is empty
  core::Pose X_palm_obj;   // pose of the object body in the palm frame, fixed at grasp time
  bool lid = false;        // holding the lid of a box (object) by one point, not the object
  core::Vec3 p_lid_grasp = core::Vec3::Zero();  // lid only: grasped point in the lid frame
  bool has_last_target = false;
  core::Pose X_W_last_target;  // target pose of the object at the previous step (for velocity)
};

struct Data {
  MjDataPtr mj;        // never null after make_data()
  MjDataPtr scratch;   // a second mjData for differential IK (never the simulated state; made
                       // without the constraint arena: kinematics and Jacobians only)
  std::vector<mjtNum> jacobian;  // 6 x nv scratch for IK (allocated by make_data)

  // Robot controller targets (what the servos track; written to mj->ctrl).
  model::JointVector q_target;     // rad, one per arm joint, within the joint limits
  double gripper_width_target = 0;  // m, in [0, model.robot.gripper.max_width()]

  // Human (meaningful only if model.has_human).
  human::SkeletonPose human_pose;                         // the pose to show at the next step
  std::array<core::Pose, human::kNumJoints> X_WJ{};       // joint frames of the posed human
  bool human_pose_dirty = true;                           // X_WJ/mocap not yet updated
  std::array<HoldState, 2> hold{};                        // by static_cast<size_t>(Side)

  double time() const { return mj->time; }  // simulated time since reset, s

  Data() = default;
  Data(Data&&) = default;
  Data& operator=(Data&&) = default;
  Data(const Data&) = delete;
  Data& operator=(const Data&) = delete;
};

// Allocates a Data for `model` and resets it (reset()).
Data make_data(const model::Model& model);

// Copies the whole state of `from` into `to` (both made for `model` by make_data): MuJoCo's
// state with mj_copyData, the controller targets, the human pose and holds. Stepping both on
// with the same inputs gives the same states bit for bit. Allocation-free.
void copy_data(const model::Model& model, const Data& from, Data& to);

// Resets to the start of an episode without allocating: the robot at the home keyframe
// (fingers open, servo targets = home), objects at their spec poses (held objects in the hand),
// the human at model.human_start, time 0, warning counts cleared; then mj_forward.
void reset(const model::Model& model, Data& data);
// As reset(), with the human starting at `human_start` (held objects are placed in the hand
// of that pose).
void reset(const model::Model& model, Data& data, const human::SkeletonPose& human_start);

// Sets the human pose shown from the next step on. Call it every physics step for smooth
// motion (the mocap bodies jump to the new pose). No-op without a human.
void set_human_pose(const model::Model& model, Data& data, const human::SkeletonPose& pose);

// Applies data.human_pose to the mocap bodies and data.X_WJ if it changed (forward
// kinematics); step() and forward() call it. No-op without a human.
void pose_human(const model::Model& model, Data& data);

// One physics step (model::kTimestep): prepare_step, then mj_step. Allocation-free.
void step(const model::Model& model, Data& data);
// Everything step() gives mj_step besides the state: the human's mocap poses (pose_human), the
// hold wrenches (xfrc_applied) and the arm's gravity compensation (qfrc_applied), on top of
// the servo targets already in ctrl. After it, mjData holds every input of the physics step.
void prepare_step(const model::Model& model, Data& data);

// Recomputes MuJoCo's derived quantities (positions, contacts, forces) for the current state
// (mj_forward), after posing the human if its pose changed.
void forward(const model::Model& model, Data& data);

// The frames of the current state, for observing it, without forward()'s dynamics: after posing
// the human, MuJoCo's kinematics (body, geom, site, camera and light poses; centres of mass)
// and the bodies' velocities (mj_kinematics, mj_comPos, mj_camlight, mj_comVel). The contacts
// and their forces stay those the last physics step began from, and nothing the next step
// starts from changes: the solver's warm start, the bias forces and qpos (forward() normalises
// the free bodies' quaternions) stay as that step left them.
void observe_state(const model::Model& model, Data& data);

// MuJoCo warnings counted since the last reset (sum over mjData.warning[].number), and a
// one-line description ("" if none), e.g. "BADQACC x1 (info 12)".
int warning_count(const Data& data);
std::string warning_summary(const Data& data);

// Short name of MuJoCo warning slot `i` (mjtWarning order: 0 = "INERTIA" ... mjNWARNING - 1 =
// "BADCTRL"); "?" outside [0, mjNWARNING). Inline so test support can share it without linking.
inline const char* warning_name(int i) {
  static constexpr std::array<const char*, mjNWARNING> kNames = {
      "INERTIA", "CONTACTFULL", "CNSTRFULL", "VGEOMFULL", "BADQPOS", "BADQVEL", "BADQACC",
      "BADCTRL"};
  return i >= 0 && i < mjNWARNING ? kNames[static_cast<size_t>(i)] : "?";
}

}  // namespace hribench::sim
