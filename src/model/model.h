#pragma once
// The world as an immutable MuJoCo model: a robot (a description of model/robot.h, by default
// the Franka Panda with the Franka Hand) on a table, graspable objects, and a kinematic human
// body (one mocap body per skeleton joint carrying capsules). Built from a plain SceneSpec by generating MJCF text in C++ and loading it through
// MuJoCo 2.2.2's virtual file system (no files are read or written).
//
// World frame W (core/math.h): z up, floor at z = 0, x from the robot base toward the human,
// y to the robot's left. The robot base frame B is on the table top at (0, 0, table_top_z):
// X_WB = translation (0, 0, 0.75). The table spans x in [table_x_min, table_x_max] and
// y in [-table_width/2, table_width/2]; its top is at z = table_top_z.
//
// A Model is immutable after build() and may be shared read-only between threads; all state
// lives in sim::Data (sim/data.h).

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <mujoco/mujoco.h>

#include "core/math.h"
#include "human/skeleton.h"
#include "model/robot.h"

namespace hribench::model {

// ---------------------------------------------------------------------------------------------
// Scene specification (the input of build()).

// Object kinds. Names used in specs: "cube", "cup", "bottle", "plate", "bin", "tray", "box"
// (a box with a hinged lid), "plank".
enum class ObjectKind { kCube, kCup, kBottle, kPlate, kBin, kTray, kBox, kPlank };
inline constexpr int kNumObjectKinds = 8;
std::string_view to_string(ObjectKind kind);
std::optional<ObjectKind> object_kind_from_name(std::string_view name);

// RGBA colour, components in [0, 1].
struct Rgba {
  float r = 0, g = 0, b = 0, a = 1;
};
// Named colours: the object catalogue's (script/catalogue.h), and "grey", the old spelling of
// "gray" (eval's script driver still passes it).
std::optional<Rgba> colour_from_name(std::string_view name);
// All colour names accepted by colour_from_name, in a fixed order.
const std::vector<std::string_view>& colour_names();

// One object of the scene. Every object is a free body (freejoint); the box's lid is a hinged
// child body of the box.
struct ObjectSpec {
  std::string kind = "cube";  // see ObjectKind; anything else is an InputError
  std::string name;           // unique among objects; [A-Za-z0-9_]+; default: "<kind><index>"
  std::string colour = "red"; // see colour_from_name
  // Position of the object's footprint centre on the table top (world frame, m) and its yaw
  // about +z (rad). The object rests on the table (its bottom at table_top_z), or in its
  // container (inside) or on its platform (on). The footprint must lie inside the table top.
  // Ignored when held_by is set.
  double x = 0.5;
  double y = 0.0;
  double yaw = 0.0;
  // Scale of the object's nominal dimensions, in [0.5, 2] (1 = nominal sizes; see
  // ObjectInfo::half_extents).
  double size_scale = 1.0;
  // Human hands (the wrist bodies' capsules) never collide with objects (nor box lids); the
  // other human capsules do.
  // If set, the object starts in this human hand (held, see sim::hold) instead of on the table.
  std::optional<human::Side> held_by;
  // If set, the object starts inside this container (the name of an open-top bin, tray or box
  // of the spec), resting on its floor: x/y are still its footprint centre in world, and its
  // footprint must lie within the container's inner walls (a box's item must also fit under
  // the closed lid). Not with held_by or on.
  std::string inside;
  // If set, the object starts resting on this platform (a PlatformSpec name): its bottom at the
  // platform's top, its footprint centre over the platform (it may overhang). Not with
  // held_by or inside.
  std::string on;
};

struct HumanSpec {
  bool present = true;       // false: no human body in the model
  double height = 1.75;      // standing height, m, in [1.0, 2.5] (tasks use 1.55-1.95)
  // Standing position of the pelvis projected on the floor (world, m) and facing yaw about +z
  // (rad; pi = facing -x, i.e. toward the robot). Default: at the far table edge.
  double x = 1.45;
  double y = 0.0;
  double yaw = core::kPi;
  human::Side handedness = human::Side::kRight;
};

// A raised platform: a fixed box standing on the table top (e.g. the support a plank starts on
// and the platform it is lowered onto in co_lift). Objects may not start overlapping its
// footprint unless they rest on it (ObjectSpec::on).
struct PlatformSpec {
  std::string name;                  // unique among platforms, [A-Za-z0-9_]+; default "platform<i>"
  double x = 0.6, y = 0.3, yaw = 0;  // footprint centre on the table (world, m) and yaw (rad)
  double length = 0.7;               // along its x axis, m
  double width = 0.25;               // along its y axis, m
  double height = 0.12;              // above the table top, m, in [0.02, 0.5]
};

struct SceneSpec {
  // The robot on the table: a description's name (robot_by_name; an unknown name is an
  // InputError of build()).
  std::string robot = std::string(kDefaultRobot);
  std::vector<ObjectSpec> objects;
  HumanSpec human;
  std::vector<PlatformSpec> platforms;
  // Light intensity multiplier in [0.2, 2] (lighting variation axis).
  double light_intensity = 1.0;
  // Lights cast shadows (MuJoCo's shadow map; costly on llvmpipe). Off by default.
  bool shadows = false;
  // A hidden square foot inside the round base of every cup and bottle (massless, 2 mm high at
  // scale 1). MuJoCo 2.2.2 gives a cylinder on a box one contact point, on which a cup standing
  // on the table rocks for ever at the 5 ms step; the foot's box-box contacts hold it. On since
  // pool v7; off is the physics candidate no-base-feet of `hribench bench --episodes`
  // (docs/performance.md, "Physics").
  bool base_feet = true;

  // A default scene: the default robot (the Panda), table, a red cube, a green cup, a blue
  // bin, and a human standing at the far edge facing the robot.
  static SceneSpec Default();
};

// ---------------------------------------------------------------------------------------------
// Fixed scene geometry (the scene convention of docs/tasks.md).

inline constexpr double kTableTopZ = 0.75;      // m
inline constexpr double kTableXMin = -0.15;     // near edge (robot side), m
inline constexpr double kTableXMax = 1.05;      // far edge (human side), m
inline constexpr double kTableWidth = 1.0;      // along y, m
inline constexpr double kTimestep = 0.005;      // s (200 Hz physics; docs/performance.md, "Physics")

// MuJoCo's preallocated arena of every mjData (docs/performance.md). MuJoCo 2.2.2 sizes the
// constraint arrays by njmax, among them the njmax x njmax matrix efc_AR, and clears the whole
// buffer whenever an mjData is made (the state's, per episode: the compiler's and the IK
// scratch's are made without the arena), so these sizes are a cost of every episode, not only a
// limit. kMaxContacts is 3.5x the most contacts `hribench bench --episodes` saw in a task
// episode (56, over the 13 tasks x the 4 built-in policies x 2 seeds); the constraint rows
// hold a full contact list at the largest condim (4, objects: elliptic cones give one row per
// dimension) plus 200 rows of joint limits and equalities, so the contact list fills first (a
// MuJoCo warning, status invalid) and the sizes never change an episode that fits them.
inline constexpr int kMaxContacts = 200;                           // nconmax
inline constexpr int kMaxConstraintRows = 4 * kMaxContacts + 200;  // njmax

// The hands' shapes (human::HandShape) ride in mjData::userdata for the renderers, which draw
// each hand's fingers in place of its contact capsule (render/renderer.h, human/hand.h): left
// grip, left point, right grip, right point (sim::pose_human writes them). The person's height,
// which sizes the hands, is the model's numeric named kHumanHeightNumeric.
inline constexpr int kHandShapeValues = 4;
inline constexpr const char* kHumanHeightNumeric = "human_height";

// ---------------------------------------------------------------------------------------------
// Geom tags: who every geom of the model belongs to.

enum class GeomOwner {
  kOther,        // e.g. decorative geoms
  kFloor,
  kTable,
  kRobotLink,    // index = link number in Robot::links (0 = base)
  kRobotHand,    // the hand body (palm housing)
  kRobotFinger,  // index = 0 (left finger) or 1 (right finger); includes the finger pads
  kHuman,        // index = capsule index in Model::human_capsules; region/joint set
  kObject,       // index = object index in Model::objects
  kPlatform,     // a raised platform; index = platform index in Model::platforms
};
std::string_view to_string(GeomOwner owner);

struct GeomTag {
  GeomOwner owner = GeomOwner::kOther;
  int index = -1;  // meaning depends on owner (see GeomOwner); -1 when none
  human::BodyRegion region = human::BodyRegion::kTorso;  // meaningful only for kHuman
  human::Joint joint = human::Joint::kPelvis;             // meaningful only for kHuman
  bool is_robot() const {
    return owner == GeomOwner::kRobotLink || owner == GeomOwner::kRobotHand ||
           owner == GeomOwner::kRobotFinger;
  }
  bool is_human() const { return owner == GeomOwner::kHuman; }
};

// ---------------------------------------------------------------------------------------------
// The built model.

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};

struct ObjectInfo {
  std::string name;
  ObjectKind kind = ObjectKind::kCube;
  Rgba rgba;
  int body = -1;       // MuJoCo body id of the object's root (free) body
  int qpos_adr = -1;   // freejoint qpos address (7: position, quaternion w x y z)
  int dof_adr = -1;    // freejoint dof address (6: linear world velocity, angular body-frame)
  double mass = 0;     // total mass including children (kg)
  // Half extents of the object's bounding box in its body frame (m). The body frame origin is
  // at the centre of the footprint on the bottom face (z up), so the object occupies
  // [-hx, hx] x [-hy, hy] x [0, 2 hz].
  core::Vec3 half_extents = core::Vec3::Zero();
  // Pose of the object body in world at reset (on the table, in its container, on its
  // platform, or in the hand if held_by).
  core::Pose X_W_start;
  std::optional<human::Side> held_by;  // from the spec
  int lid_body = -1;   // kBox only: the lid body, else -1
  int lid_joint = -1;  // kBox only: the lid hinge joint id (0 = closed), else -1
  // Default pose of the object body in the palm frame (see Model::X_wrist_palm) of the hand
  // that holds it from the start (held_by; else the handedness hand): upright in the start
  // pose, its centre just off the palm along the palm normal (outside the hand capsule).
  core::Pose X_palm_hold;
};

// A built platform: a static box geom (GeomTag owner kPlatform, index = platform index).
struct PlatformInfo {
  std::string name;
  int geom = -1;                                 // MuJoCo geom id
  core::Pose X_WC;                               // pose of the box's centre in world (yaw only)
  core::Vec3 half_extents = core::Vec3::Zero();  // half sizes (length, width, height) / 2, m
};

// Height of the floor's top above the bottom of an open container (bin, tray, box), i.e. where
// an object inside rests, m; 0 for other kinds.
double container_floor_height(ObjectKind kind, double size_scale);

struct Model {
  SceneSpec spec;  // the spec it was built from, defaults resolved (e.g. object names)
  std::unique_ptr<mjModel, MjModelDeleter> mj;  // never null after build()
  std::string mjcf;                             // the generated MJCF text (for inspection)

  const mjModel* m() const { return mj.get(); }

  // The robot's description (robot_by_name(spec.robot)): its dof, joint limits, gripper range.
  Robot robot;
  // Robot ids and addresses, one per arm joint (robot.joints) or link (robot.links).
  std::vector<int> arm_joint;     // joint ids
  std::vector<int> arm_qpos_adr;  // qpos addresses
  std::vector<int> arm_dof_adr;   // dof addresses
  std::vector<int> arm_actuator;  // position-servo actuator ids (ctrl = target, rad)
  // The servos' damping is in the joints' and sim::step adds it back (servo_damping_in_joints(),
  // as built); false after servo_damping_in_servos().
  bool servo_damping_in_joints = false;
  std::vector<int> link_body;     // link body ids, base first
  std::array<int, 2> finger_joint{};        // left/right finger slide joints
  std::array<int, 2> finger_qpos_adr{};
  std::array<int, 2> finger_dof_adr{};
  std::array<int, 2> finger_body{};
  int gripper_actuator = -1;  // ctrl = target opening width in m (0..robot.gripper.max_width())
  int hand_body = -1;         // the hand body (hand frame = body frame)
  int flange_site = -1;       // site at the flange (robot.flange in the last link's frame)
  int tcp_site = -1;          // site at the TCP: hand frame + robot.gripper.tcp_offset along z_hand
  core::Pose X_WB;            // robot base pose in world

  // Cameras (MuJoCo camera ids): "agentview" (front/above, fixed) and "wrist" (on the hand,
  // looking along the fingers).
  int agentview_camera = -1;
  int wrist_camera = -1;

  // Human (present only if spec.human.present; otherwise the ids are -1 and vectors empty).
  bool has_human = false;
  human::Skeleton skeleton;                       // scaled from spec.human.height
  std::vector<human::BodyCapsule> human_capsules; // capsule i <-> geom human_capsule_geom[i]
  std::vector<int> human_capsule_geom;            // geom id of each capsule
  std::array<int, human::kNumJoints> human_body{};   // body id per joint (-1 if absent)
  std::array<int, human::kNumJoints> human_mocap{};  // mocap index per joint (-1 if absent)
  // Pose at reset: standing at the spec position, arms hanging; a hand that holds an object
  // from the start (ObjectSpec::held_by) has its forearm bent forward 90 deg.
  human::SkeletonPose human_start;
  // Palm frame of each hand (index by static_cast<size_t>(Side)), relative to the wrist joint
  // frame, in the human layer's hand convention (human/arm_ik.h): origin at the palm centre
  // (skeleton.palm_distance along -z of the wrist frame), x axis along the fingers (-z of the
  // wrist frame), z axis = palm normal (the way the palm faces: -y of the wrist frame for the
  // left hand, +y for the right, i.e. toward the midline at rest). MuJoCo sites "palm_left" /
  // "palm_right" on the wrist bodies mark it.
  std::array<core::Pose, 2> X_wrist_palm;

  // Objects, in spec order.
  std::vector<ObjectInfo> objects;
  // Object index by name, or -1.
  int object_index(std::string_view name) const;

  // One tag per geom (size m()->ngeom).
  std::vector<GeomTag> geom_tags;

  // Fixed geoms.
  int table_geom = -1;
  int floor_geom = -1;
  // Platforms, in spec order (a platform's top is at kTableTopZ + its height).
  std::vector<PlatformInfo> platforms;
  // Platform index by name, or -1.
  int platform_index(std::string_view name) const;

  Model() = default;
  Model(Model&&) = default;
  Model& operator=(Model&&) = default;
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;
};

// Builds the model. Throws core::InputError on a bad spec (unknown object kind or colour,
// duplicate or malformed name, object off the table, bad size_scale/height/light, an object
// inside something that is not a container of the spec or not fitting in it, an object on an
// unknown platform) or if MuJoCo
// rejects the generated MJCF (a bug: the message carries MuJoCo's error).
Model build(const SceneSpec& spec);

// The arm's servo model the Euler integrator integrates, as build() leaves it
// (docs/performance.md, "Physics"). Each arm servo's damping kv (the bias's velocity gain,
// −biasprm[2]) is added to its joint's damping, which Euler integrates implicitly, and stays in
// the servo, whose force limit clamps kp·e − kv·q̇; sim::step adds kv·q̇ back to the applied
// forces unclamped. So the damping the servo asks for is integrated implicitly and its force
// limit still applies to the same sum. The gripper's servo keeps its damping (Euler takes it
// explicitly: the fingers' armature is sized for it). Expects the arm's joints damped as the
// robot's description says; leaves the integrator to the caller.
void servo_damping_in_joints(Model& model);

// The arm's servos of pool v4 and before, which the implicit integrator integrated: the joints
// damped as the robot's description says, the damping in the servos alone, nothing added back
// (the `implicit` candidate of `hribench bench --episodes --physics`, and tests that compare).
// Leaves the integrator to the caller.
void servo_damping_in_servos(Model& model);

// A servo's damping kv (N·m·s/rad, or N·s/m for the gripper): its bias's velocity gain, −biasprm[2].
double servo_kv(const mjModel& m, int actuator);

// The MJCF text that build() loads (for inspection and tests); throws like build(). build()
// then adds the arm servos' damping to the joints' (servo_damping_in_joints), which this text
// does not show.
std::string to_mjcf(const SceneSpec& spec);

}  // namespace hribench::model
