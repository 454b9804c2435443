#pragma once
// The Policy interface (docs/design.md): the runner calls reset(EpisodeInfo) once per episode,
// then act(Observation) -> ActionChunk whenever it needs actions; it executes
// `replan_every` actions of a chunk (or the whole chunk, if shorter) before asking again.
//
// A policy declares what it consumes in its PolicySpec (cameras and their size, the state
// track on/off, its action space); the runner renders only the cameras asked for and fills the
// state track only when asked. The script's internal phase is never observed.
//
// Units: metres, radians, seconds; poses are X_WB (pose of B in world, core/math.h).
// Robot-specific sizes and bounds (joint vectors, joint_pos actions, their limits, the gripper's
// opening) come from the episode's robot description (model/robot.h, EpisodeInfo::robot).
// Adding a policy never touches the runner: implement Policy and register a factory by name
// (policy/registry.h).

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.h"
#include "model/robot.h"
#include "script/scenario.h"

namespace hribench::policy {

inline constexpr int kHumanKeypoints = 22;   // SMPL joints (human/skeleton.h)

// ee_delta: [dx, dy, dz (m, world frame), drx, dry, drz (rad, axis-angle in world frame),
//            gripper]; one control step's change of the TCP pose (differential IK).
// joint_pos: [q_1..q_dof (rad, absolute targets, one per arm joint of the robot), gripper].
// gripper: target opening as a fraction of the robot's full opening (gripper.max_width()),
// 0 = closed, 1 = fully open.
enum class ActionSpace { kEeDelta, kJointPos };
std::string_view to_string(ActionSpace space);  // "ee_delta" | "joint_pos"
// Throws core::InputError (where = `where`) for an unknown name.
ActionSpace action_space_from_string(std::string_view name, std::string_view where);
// Values per action for a robot with `dof` arm joints: 7 for ee_delta, dof + 1 for joint_pos.
int action_dim(ActionSpace space, size_t dof);
int action_dim(ActionSpace space, const model::Robot& robot);

// One camera a policy wants, rendered at width x height (pixels).
struct CameraRequest {
  std::string name;  // e.g. "agentview", "wrist"
  int width = 224;
  int height = 224;
};

// What a policy consumes and produces.
struct PolicySpec {
  std::vector<CameraRequest> cameras;  // empty: no images are rendered
  bool state_track = false;            // true: human keypoints and object poses are observed
  ActionSpace action_space = ActionSpace::kEeDelta;
  int replan_every = 1;  // actions executed per chunk before asking again (>= 1)
  // true: the episode's sampled script (EpisodeInfo::episode) and its events as they happen
  // (Observation::events) are observed. For privileged experts (the oracle and its scripted
  // baselines), never for a policy under evaluation as a learner.
  bool privileged = false;
  // While the policy thinks (a latency other than none, eval/runner.h): false holds the last
  // command; true keeps executing the rest of the previous chunk (the actions after the first
  // replan_every), then holds once it runs out, as deployed chunking policies run.
  bool execute_while_thinking = false;
};

// Facts about the episode a policy may know before the first observation.
struct EpisodeInfo {
  std::string task;         // e.g. "handover_h2r"
  std::string instruction;  // the language instruction
  uint64_t seed = 0;        // the episode's seed (a policy may seed its own randomness)
  double horizon = 30.0;    // s
  double control_dt = 0.05; // s between control steps
  // The robot's description name (model::robot_by_name): its dof sizes the proprioception and
  // joint_pos actions, its joint limits and gripper range bound them.
  std::string robot = std::string(model::kDefaultRobot);
  // Privileged policies only (PolicySpec::privileged), else null: the sampled episode (scene,
  // human, acts with their goals, success) whose events Observation::events reports.
  std::shared_ptr<const script::EpisodeSpec> episode;
};

// An RGB image, uint8, row-major HWC (height x width x 3).
struct Image {
  std::string camera;
  int width = 0;
  int height = 0;
  std::vector<uint8_t> pixels;  // size height * width * 3
};

// The robot's own state; joint vectors hold one value per arm joint of the episode's robot.
struct Proprioception {
  model::JointVector joint_pos;  // rad
  model::JointVector joint_vel;  // rad/s
  double gripper_width = 0;      // m, 0 .. the robot's gripper.max_width()
  core::Pose X_WT;                             // tool centre point in world
};

// Pose of a named scene object (state track only).
struct ObjectPose {
  std::string name;
  core::Pose X_WO;
};

// The state track: what a perfect perception system would report.
struct StateObservation {
  std::array<core::Vec3, kHumanKeypoints> human_joints_W = [] {  // SMPL joint positions, world
    std::array<core::Vec3, kHumanKeypoints> joints;
    joints.fill(core::Vec3::Zero());
    return joints;
  }();
  std::vector<ObjectPose> objects;                           // sorted by name
};

// An event of the running scenario, as the episode log records it (privileged track only).
struct ScriptEvent {
  double time = 0;   // s
  std::string kind;  // "act_start" | "act_end" | "phase" | "cue" | "predicate_change" | "warning"
  std::string name;  // e.g. "offer.start", "offer.hold_stable", "take.end", "in(item, bin)"
  std::string detail;  // cue: the cue kind ("go" | "stop" | "intrusion"); predicate: "true"/"false"
};

struct Observation {
  double time = 0;  // simulated time, s
  std::string instruction;
  Proprioception proprio;
  std::vector<Image> images;              // one per requested camera, in request order
  std::optional<StateObservation> state;  // set iff the policy asked for the state track
  std::vector<ScriptEvent> events;  // privileged only: every event so far, in time order
};

// One action: action_dim(space, robot) values (see ActionSpace).
using Action = std::vector<double>;

struct ActionChunk {
  ActionSpace space = ActionSpace::kEeDelta;
  std::vector<Action> actions;  // executed in order, one per control step
};

// Bounds a returned action must respect (out of range is an error, never clipped silently):
// the benchmark's per-step bounds of ee_delta, and for joint_pos the robot's joint limits and
// dof (action_limits(robot); a default ActionLimits has none and validates ee_delta only).
struct ActionLimits {
  double max_ee_translation = 0.05;  // |dx|,|dy|,|dz| per control step, m (1 m/s at 20 Hz)
  double max_ee_rotation = 0.25;     // |drx|,|dry|,|drz| per control step, rad
  std::string robot;                 // the robot whose joints these are ("" without joints)
  model::JointVector q_min;          // rad, one per arm joint
  model::JointVector q_max;          // rad
};
// The default ee_delta bounds with `robot`'s name, joint limits and dof.
ActionLimits action_limits(const model::Robot& robot);

// What went wrong with a policy; the runner turns it into EpisodeStatus::kPolicyError.
enum class PolicyErrorKind {
  kWrongSpace,  // the chunk's action space is not the declared one
  kEmptyChunk,  // no actions
  kWrongShape,  // an action has the wrong number of values
  kNonFinite,   // NaN or infinity
  kOutOfRange,  // outside ActionLimits or the gripper's [0, 1]
  kFailed,      // the policy itself failed (server gone, exception inside the policy)
};
std::string_view to_string(PolicyErrorKind kind);

class PolicyError : public std::runtime_error {
 public:
  PolicyError(PolicyErrorKind kind, const std::string& message);
  PolicyErrorKind kind() const { return kind_; }

 private:
  PolicyErrorKind kind_;
};

// Throws PolicyError if `chunk` is not a well-formed chunk in `expected` space within `limits`.
// The message names the action index and value index ("action 2 value 3: ..."), and for a
// wrong size the expected count ("expected 8 values (joint_pos: 7 joints of panda + gripper),
// got 7"). joint_pos needs limits with joints (action_limits; HRIB_CHECK).
void validate_chunk(const ActionChunk& chunk, ActionSpace expected, const ActionLimits& limits);

class Policy {
 public:
  virtual ~Policy() = default;
  // The policy's declared needs; constant over the policy's life.
  virtual PolicySpec spec() const = 0;
  // Starts an episode. Throws PolicyError(kFailed) if the policy cannot start.
  virtual void reset(const EpisodeInfo& info) = 0;
  // Actions for the observation; the runner validates them (validate_chunk).
  virtual ActionChunk act(const Observation& observation) = 0;
};

}  // namespace hribench::policy
