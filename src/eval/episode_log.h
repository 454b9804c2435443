#pragma once
// EpisodeLog: everything an episode leaves behind (docs/design.md) — one StepRecord per control
// step plus timed Events and the episode's status. Enough to recompute every metric
// (eval/metrics.h) without re-simulating, and to replay the episode.
//
// Units: metres, seconds, newtons; poses X_WB (pose of B in world). Steps are in increasing
// time; step k describes the world at time steps[k].time. Quantities that describe a motion
// over the step interval (t_{k-1}, t_k] are derived by the metrics from consecutive steps.
//
// Files: save_episode_log / load_episode_log use a compact little-endian binary format:
//   "HRIBLOG\0" | u32 format version | u64 payload size | payload | u64 FNV-1a of payload.
// Doubles are stored bit for bit, so a reloaded log is identical to the saved one. A file of
// another format version is refused (core::InputError naming both versions); docs/episode.md
// describes the fields.
//
// Version 2 (this one) adds to each step what the robot was told (the action, the servo
// targets, the gripper command), joint velocities, finger positions, lid angles and the human's
// full skeleton pose, so a log alone re-renders (pose_from_step, eval/episode.h), replays and
// makes a dataset.

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/errors.h"
#include "core/math.h"
#include "human/skeleton.h"
#include "policy/policy.h"

namespace hribench::eval {

inline constexpr uint32_t kEpisodeLogVersion = 3;

// What the robot touched.
enum class ContactOther {
  kHuman,        // a human body capsule (region set)
  kEnvironment,  // table, container wall, box lid, floor: counted as a collision (CFR)
  kObject,       // a manipulated object (expected; never a collision by itself)
};
std::string_view to_string(ContactOther other);

// One robot contact at one control step (summed over MuJoCo contact points of the geom pair).
struct Contact {
  std::string robot_part;        // robot geom/body name, e.g. "panda_link5", "left_finger_pad"
  bool robot_finger = false;     // the part is a finger (pad): allowed to touch things
  ContactOther other_kind = ContactOther::kObject;
  std::string other;             // e.g. "right_hand" (human capsule), "table", "bin_wall"
  std::optional<human::BodyRegion> region;  // set iff other_kind == kHuman
  double normal_force = 0;       // N, >= 0

  bool operator==(const Contact&) const = default;
};

// Eigen vectors are not zeroed by {}: every joint position starts at the origin explicitly.
inline std::array<core::Vec3, human::kNumJoints> zero_joints() {
  std::array<core::Vec3, human::kNumJoints> joints;
  joints.fill(core::Vec3::Zero());
  return joints;
}

struct StepRecord {
  double time = 0;                      // s
  std::vector<double> joint_pos;        // robot arm joint positions, rad
  std::vector<double> joint_vel;        // robot arm joint velocities, rad/s
  core::Pose X_WT;                      // end effector (TCP) pose
  double gripper_width = 0;             // m, the two fingers' opening
  std::array<double, 2> finger_pos{};   // m, left and right finger slide positions
  // What the robot was told over the interval (t_{k-1}, t_k] that ends at this step:
  // the action applied at its start, in EpisodeLog::action_space (empty at step 0 and while
  // the previous command is held, e.g. while the policy thinks under a latency), and the
  // servo targets in force: arm joint targets (rad) and the gripper command (opening, m).
  policy::Action action;
  std::vector<double> joint_target;
  double gripper_target = 0;
  // SMPL joint positions (zero when there is no human).
  std::array<core::Vec3, human::kNumJoints> human_joints_W = zero_joints();
  // The human's full skeleton pose shown at this step: root X_WP and each joint's rotation
  // relative to its parent (the rest pose when there is no human).
  human::SkeletonPose human_pose;
  std::vector<core::Pose> object_poses; // X_WO, aligned with EpisodeLog::object_names
  // Articulation of each object, aligned with object_names: a box's lid hinge angle, rad
  // (0 = closed); 0 for objects without one.
  std::vector<double> lid_angles;
  // d(t): minimum distance between any robot geom and any human geom, m (+infinity when
  // there is no human). Negative = penetration.
  double separation = 0;
  // Velocity of the robot's closest point (to the human) projected on the direction toward
  // the human's closest point, m/s; > 0 approaching, < 0 moving away.
  double approach_speed = 0;
  // Speed (norm of the velocity) of the robot's closest point, m/s.
  double closest_point_speed = 0;
  std::vector<Contact> contacts;        // sorted by (robot_part, other)
  // Truth of each logged predicate series, aligned with EpisodeLog::predicate_names.
  std::vector<uint8_t> predicates;
};

enum class EventKind {
  kActStart,         // an act began (name "ACT.start")
  kActEnd,           // an act ended; for robot acts: its goal first held (name "ACT.end")
  kPhase,            // a human motion phase began (name "ACT.PHASE", e.g. "offer.hold_stable")
  kCue,              // a cue was given (name = the cue's event)
  kPredicateChange,  // a logged predicate changed (name = predicate, detail "true"/"false")
  kContactBegin,     // a robot contact pair began (name "robot_part|other")
  kContactEnd,
  kWarning,          // anything odd (detail = text)
};
std::string_view to_string(EventKind kind);

enum class Actor { kNone, kHuman, kRobot };
std::string_view to_string(Actor actor);

struct Event {
  double time = 0;  // s
  EventKind kind = EventKind::kWarning;
  Actor actor = Actor::kNone;
  std::string name;
  std::string detail;

  bool operator==(const Event&) const = default;
};

struct EpisodeLog {
  // Identity of the episode.
  std::string task;       // e.g. "handover_h2r"
  std::string role;       // "instructor" | "collaborator" | "intruder"
  std::string spec_hash;  // content hash of the EpisodeSpec
  uint64_t seed = 0;
  std::string policy;     // policy reference, e.g. "noop"
  std::string robot;      // the robot description's name (model/robot.h), e.g. "panda"
  double horizon = 0;     // s
  double control_dt = 0;  // s
  policy::ActionSpace action_space = policy::ActionSpace::kEeDelta;  // of StepRecord::action
  // Names of the per-step series.
  std::vector<std::string> object_names;     // StepRecord::object_poses
  std::vector<std::string> predicate_names;  // StepRecord::predicates
  // Trace.
  std::vector<StepRecord> steps;
  std::vector<Event> events;  // in time order
  // How it ended.
  core::EpisodeStatus status = core::EpisodeStatus::kOk;
  std::string status_reason;  // empty when kOk

  // Index of a predicate series, or nullopt.
  std::optional<size_t> predicate_index(std::string_view name) const;
  // Time of the first event named `name`, or nullopt.
  std::optional<double> event_time(std::string_view name) const;
  // Duration covered by the steps (last time - first time; 0 when fewer than two steps).
  double duration() const;
};

// True iff the two logs are bit for bit the same (every double compared by its bits, so a NaN
// equals itself and 0.0 differs from -0.0): the determinism and round-trip check.
bool identical(const EpisodeLog& a, const EpisodeLog& b);

// Checks the log's internal consistency (times increasing, series sizes matching the name
// lists, forces >= 0, human contacts carry a region); throws core::InputError naming the first
// problem (where = `where`, e.g. the file name).
void check_episode_log(const EpisodeLog& log, std::string_view where);

// Binary encoding (format above).
std::string encode_episode_log(const EpisodeLog& log);
// Throws core::InputError (where = `where`) for a truncated, corrupt or foreign byte string,
// or one of another format version.
EpisodeLog decode_episode_log(std::string_view bytes, std::string_view where);

// File round trip. save writes a temporary file next to `path` and renames it over `path`
// (a reader never sees half a log); it throws core::InputError if the file cannot be written.
void save_episode_log(const EpisodeLog& log, const std::filesystem::path& path);
EpisodeLog load_episode_log(const std::filesystem::path& path);

}  // namespace hribench::eval
