#pragma once
// Internal to the model layer: pieces of the generated MJCF text. Each generator appends
// XML to a string; build() in model.cc assembles them and loads the result.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.h"
#include "model/model.h"

namespace hribench::model::mjcf {

// Collision bits (contype / conaffinity). MuJoCo makes a contact between geoms a and b if
// (contype_a & conaffinity_b) || (contype_b & conaffinity_a).
inline constexpr int kBitStatic = 1;  // floor, table
inline constexpr int kBitRobot = 2;
inline constexpr int kBitObject = 4;
inline constexpr int kBitHuman = 8;

// Number formatting for MJCF attributes ("%.9g").
std::string num(double v);
std::string vec(const core::Vec3& v);
std::string quat(const core::Quat& q);  // "w x y z"
std::string rgba(const Rgba& c);
// xyaxes="..." for a camera at `pos` looking at `target`, with image x perpendicular to `up`
// (image up as close to `up` as possible). All in the parent body's frame.
std::string camera_xyaxes(const core::Vec3& pos, const core::Vec3& target,
                          const core::Vec3& up = core::Vec3::UnitZ());

// Writes shapes as geoms named "<prefix>_g<i>" of default class `cls` whose masses sum to
// `mass` (split by volume). `extra` is appended inside each geom tag (e.g. rgba="...").
void shape_geoms(const std::vector<Shape>& shapes, double mass, std::string_view name_prefix,
                 std::string_view cls, std::string& out, std::string_view extra = "");

// The robot `robot` as a <body> tree with its base link at `base` (world, m), appended to
// `worldbody`; its gripper tendon and finger coupling (appended to `tendon`, `equality`), its
// servos (appended to `actuator`) and its geom default classes (appended to `defaults`).
// Names: the description's links, joints and actuators; "flange", "hand", "tcp", the wrist
// camera, "left_finger"/"right_finger", "finger_joint1"/"finger_joint2", "gripper".
void robot(const Robot& robot, const core::Vec3& base, std::string& defaults,
           std::string& worldbody, std::string& tendon, std::string& equality,
           std::string& actuator);

// Nominal half extents (body frame, origin at the bottom centre) of an object kind at scale 1.
core::Vec3 nominal_half_extents(ObjectKind kind);
// Walls of an open container (bin, tray, box) at scale s: outer half extents hx, hy, wall
// height and thickness (also the floor's), m. nullopt for other kinds.
struct ContainerWalls {
  double hx = 0, hy = 0, height = 0, thickness = 0;
};
std::optional<ContainerWalls> container_walls(ObjectKind kind, double s);
// Nominal mass (kg) at scale 1 (scales with size_scale^3).
double nominal_mass(ObjectKind kind);
// One object as a free <body> named "object_<name>" at pose X_WO (appended to `worldbody`);
// `base_foot`: SceneSpec::base_feet.
void object(const ObjectSpec& spec, ObjectKind kind, const Rgba& colour, const core::Pose& X_WO,
            bool base_foot, std::string& worldbody);

// The human body: one mocap <body> "human_<joint name>" per joint at its world pose in `pose`,
// carrying the capsules (geoms "human_<capsule name>"; the hands' not drawn, group 3) and, on the
// wrists, "palm_<side>" sites.
void human_body(const human::Skeleton& skeleton, const std::vector<human::BodyCapsule>& capsules,
                const human::SkeletonPose& pose, const std::array<core::Pose, 2>& X_wrist_palm,
                std::string& worldbody);

}  // namespace hribench::model::mjcf
