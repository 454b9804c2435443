// build(): validate a SceneSpec, generate the MJCF text, load it through MuJoCo's VFS, and
// derive the id tables of Model.

#include "model/model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "core/errors.h"
#include "model/mjcf.h"
#include "script/catalogue.h"

namespace hribench::model {
namespace {

using core::Pose;
using core::Vec3;


// Robot base keep-out radius on the table top (m): objects may not start on the base.
constexpr double kBaseKeepOut = 0.13;

bool valid_name(std::string_view name) {
  if (name.empty() || name.size() > 40) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

// Footprint corners of an object (half extents hx, hy) at (x, y, yaw), world xy.
std::array<Eigen::Vector2d, 4> footprint(double x, double y, double yaw, double hx, double hy) {
  const Eigen::Rotation2Dd r(yaw);
  const Eigen::Vector2d c(x, y);
  return {c + r * Eigen::Vector2d(hx, hy), c + r * Eigen::Vector2d(-hx, hy),
          c + r * Eigen::Vector2d(-hx, -hy), c + r * Eigen::Vector2d(hx, -hy)};
}

// 2-D separating-axis test for two convex quadrilaterals.
bool overlap(const std::array<Eigen::Vector2d, 4>& a, const std::array<Eigen::Vector2d, 4>& b) {
  for (const auto* poly : {&a, &b}) {
    for (size_t i = 0; i < 4; ++i) {
      const Eigen::Vector2d e = (*poly)[(i + 1) % 4] - (*poly)[i];
      const Eigen::Vector2d n(-e.y(), e.x());
      double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
      for (const auto& p : a) amin = std::min(amin, n.dot(p)), amax = std::max(amax, n.dot(p));
      for (const auto& p : b) bmin = std::min(bmin, n.dot(p)), bmax = std::max(bmax, n.dot(p));
      if (amax <= bmin || bmax <= amin) return false;
    }
  }
  return true;
}

// A spec with every object's kind/colour resolved and names defaulted; throws InputError.
struct Resolved {
  SceneSpec spec;
  std::vector<ObjectKind> kinds;
  std::vector<Rgba> colours;
  std::vector<Vec3> half_extents;
  std::vector<double> bottom_z;  // world z of each object's bottom at the start (not held)
};

Resolved resolve(const SceneSpec& in) {
  Resolved r{in, {}, {}, {}, {}};
  const auto finite = [](double v) { return std::isfinite(v); };
  if (!finite(in.light_intensity) || in.light_intensity < 0.2 || in.light_intensity > 2)
    throw core::InputError("scene.light_intensity", "a value in [0.2, 2]",
                           fmt::format("{}", in.light_intensity));
  const HumanSpec& h = in.human;
  if (h.present) {
    if (!finite(h.height) || h.height < 1.0 || h.height > 2.5)
      throw core::InputError("scene.human.height", "a height in [1.0, 2.5] m",
                             fmt::format("{}", h.height));
    if (!finite(h.x) || !finite(h.y) || !finite(h.yaw))
      throw core::InputError("scene.human", "finite x, y, yaw", "a non-finite value");
  }
  std::set<std::string> names;
  std::vector<std::array<Eigen::Vector2d, 4>> prints;
  std::vector<size_t> on_table;
  // Platforms.
  std::vector<std::array<Eigen::Vector2d, 4>> platform_prints;
  std::set<std::string> platform_names;
  for (size_t i = 0; i < in.platforms.size(); ++i) {
    PlatformSpec& pl = r.spec.platforms[i];
    const std::string where = fmt::format("scene.platforms[{}]", i);
    if (pl.name.empty()) pl.name = fmt::format("platform{}", i);
    if (!valid_name(pl.name))
      throw core::InputError(where + ".name", "1-40 characters of [A-Za-z0-9_]", "'" + pl.name + "'");
    if (!platform_names.insert(pl.name).second)
      throw core::InputError(where + ".name", "a name not used by another platform",
                             "duplicate '" + pl.name + "'");
    if (!finite(pl.x) || !finite(pl.y) || !finite(pl.yaw) || !finite(pl.length) ||
        !finite(pl.width) || pl.length < 0.05 || pl.width < 0.05)
      throw core::InputError(where, "finite x, y, yaw and length, width >= 0.05 m",
                             fmt::format("length {} width {}", pl.length, pl.width));
    if (!finite(pl.height) || pl.height < 0.02 || pl.height > 0.5)
      throw core::InputError(where + ".height", "a height in [0.02, 0.5] m",
                             fmt::format("{}", pl.height));
    platform_prints.push_back(footprint(pl.x, pl.y, pl.yaw, pl.length / 2, pl.width / 2));
    for (const auto& p : platform_prints.back())
      if (p.x() < kTableXMin || p.x() > kTableXMax || std::abs(p.y()) > kTableWidth / 2)
        throw core::InputError(where, "a platform footprint on the table",
                               fmt::format("off the table at x={:.3f} y={:.3f}", pl.x, pl.y));
    for (size_t k = 0; k + 1 < platform_prints.size(); ++k)
      if (overlap(platform_prints.back(), platform_prints[k]))
        throw core::InputError(where, "platforms that do not overlap",
                               fmt::format("'{}' overlaps '{}'", pl.name, r.spec.platforms[k].name));
  }
  for (size_t i = 0; i < in.objects.size(); ++i) {
    ObjectSpec& o = r.spec.objects[i];
    const std::string where = fmt::format("scene.objects[{}]", i);
    const auto kind = object_kind_from_name(o.kind);
    if (!kind) {
      std::string all;
      for (const script::ObjectKindEntry& k : script::catalogue_kinds()) {
        all += (all.empty() ? "" : ", ") + std::string(k.name);
      }
      throw core::InputError(where + ".kind", "one of " + all, "'" + o.kind + "'");
    }
    const auto colour = colour_from_name(o.colour);
    if (!colour) {
      std::string all;
      for (auto n : colour_names()) all += (all.empty() ? "" : ", ") + std::string(n);
      throw core::InputError(where + ".colour", "one of " + all, "'" + o.colour + "'");
    }
    if (o.name.empty()) o.name = fmt::format("{}{}", o.kind, i);
    if (!valid_name(o.name))
      throw core::InputError(where + ".name", "1-40 characters of [A-Za-z0-9_]",
                             "'" + o.name + "'");
    if (!names.insert(o.name).second)
      throw core::InputError(where + ".name", "a name not used by another object",
                             "duplicate '" + o.name + "'");
    if (!finite(o.size_scale) || o.size_scale < 0.5 || o.size_scale > 2)
      throw core::InputError(where + ".size_scale", "a value in [0.5, 2]",
                             fmt::format("{}", o.size_scale));
    const Vec3 half = mjcf::nominal_half_extents(*kind) * o.size_scale;
    r.kinds.push_back(*kind);
    r.colours.push_back(*colour);
    r.half_extents.push_back(half);
    const int placements = static_cast<int>(!o.inside.empty()) + static_cast<int>(!o.on.empty()) +
                           static_cast<int>(o.held_by.has_value());
    if (placements > 1)
      throw core::InputError(where, "at most one of held_by, inside and on",
                             fmt::format("'{}' has more than one", o.name));
    if (o.held_by) {
      if (!h.present)
        throw core::InputError(where + ".held_by", "a scene with a human", "no human");
      for (size_t k = 0; k < i; ++k)
        if (in.objects[k].held_by == o.held_by)
          throw core::InputError(where + ".held_by", "a free hand",
                                 fmt::format("the {} hand already holds '{}'",
                                             human::to_string(*o.held_by), r.spec.objects[k].name));
      prints.emplace_back();
      r.bottom_z.push_back(kTableTopZ);
      continue;
    }
    if (!finite(o.x) || !finite(o.y) || !finite(o.yaw))
      throw core::InputError(where, "finite x, y, yaw", "a non-finite value");
    const auto fp = footprint(o.x, o.y, o.yaw, half.x(), half.y());
    for (const auto& p : fp) {
      if (p.x() < kTableXMin || p.x() > kTableXMax || std::abs(p.y()) > kTableWidth / 2)
        throw core::InputError(
            where, fmt::format("an object footprint on the table (x in [{}, {}], |y| <= {})",
                               kTableXMin, kTableXMax, kTableWidth / 2),
            fmt::format("'{}' off the table at x={:.3f} y={:.3f}", o.name, o.x, o.y));
    }
    if (std::hypot(o.x, o.y) < kBaseKeepOut + std::hypot(half.x(), half.y()))
      throw core::InputError(where, "an object clear of the robot base",
                             fmt::format("'{}' on the base at x={:.3f} y={:.3f}", o.name, o.x, o.y));
    // Inside a container: within its inner walls, on its floor.
    double bottom = kTableTopZ;
    int container = -1;
    if (!o.inside.empty()) {
      for (size_t k : on_table)
        if (r.spec.objects[k].name == o.inside) container = static_cast<int>(k);
      const size_t k = static_cast<size_t>(container);
      const auto walls = container >= 0 ? mjcf::container_walls(r.kinds[k], r.spec.objects[k].size_scale)
                                        : std::nullopt;
      if (!walls || !r.spec.objects[k].inside.empty() || !r.spec.objects[k].on.empty())
        throw core::InputError(where + ".inside",
                               "an earlier bin, tray or box of the scene resting on the table",
                               "'" + o.inside + "'");
      const ObjectSpec& c = r.spec.objects[k];
      const bool fits = std::all_of(fp.begin(), fp.end(), [&](const Eigen::Vector2d& p) {
        const Eigen::Vector2d q = Eigen::Rotation2Dd(-c.yaw) * (p - Eigen::Vector2d(c.x, c.y));
        return std::abs(q.x()) <= walls->hx - walls->thickness + 1e-9 &&
               std::abs(q.y()) <= walls->hy - walls->thickness + 1e-9;
      });
      const bool low = r.kinds[k] != ObjectKind::kBox || 2 * half.z() <= walls->height - walls->thickness;
      if (!fits || !low)
        throw core::InputError(where + ".inside", "an object that fits within the container's walls",
                               fmt::format("'{}' does not fit in '{}'", o.name, c.name));
      bottom = kTableTopZ + walls->thickness;
    }
    // On a platform: its footprint centre over the platform, on its top.
    int platform = -1;
    if (!o.on.empty()) {
      for (size_t k = 0; k < r.spec.platforms.size(); ++k)
        if (r.spec.platforms[k].name == o.on) platform = static_cast<int>(k);
      if (platform < 0)
        throw core::InputError(where + ".on", "the name of a platform of the scene", "'" + o.on + "'");
      const PlatformSpec& pl = r.spec.platforms[static_cast<size_t>(platform)];
      const Eigen::Vector2d q = Eigen::Rotation2Dd(-pl.yaw) * Eigen::Vector2d(o.x - pl.x, o.y - pl.y);
      if (std::abs(q.x()) > pl.length / 2 || std::abs(q.y()) > pl.width / 2)
        throw core::InputError(where + ".on", "a footprint centre over the platform",
                               fmt::format("'{}' at x={:.3f} y={:.3f} is off '{}'", o.name, o.x, o.y, pl.name));
      bottom = kTableTopZ + pl.height;
    }
    for (size_t k : on_table) {
      // An object and its container, or objects on different levels, do not collide (an object
      // on the table over a container or platform was refused with that container/platform).
      if (static_cast<int>(k) == container) continue;
      if (r.spec.objects[k].inside != o.inside || r.spec.objects[k].on != o.on) continue;
      if (overlap(fp, prints[k]))
        throw core::InputError(where, "objects that do not overlap",
                               fmt::format("'{}' overlaps '{}'", o.name, r.spec.objects[k].name));
    }
    for (size_t k = 0; k < platform_prints.size(); ++k) {
      if (static_cast<int>(k) == platform || !overlap(fp, platform_prints[k])) continue;
      throw core::InputError(where, "an object clear of the platforms",
                             fmt::format("'{}' overlaps the platform '{}'", o.name,
                                         r.spec.platforms[k].name));
    }
    prints.push_back(fp);
    on_table.push_back(i);
    r.bottom_z.push_back(bottom);
  }
  return r;
}

// Palm frames in the wrist frame, in the human layer's hand convention (human/arm_ik.h):
// fingers along -z of the wrist frame, palm normal -y (left) / +y (right).
std::array<Pose, 2> palm_frames(const human::Skeleton& skeleton) {
  std::array<Pose, 2> palms;
  for (const human::Side side : {human::Side::kLeft, human::Side::kRight}) {
    const Vec3 x(0, 0, -1);
    const Vec3 z(0, side == human::Side::kLeft ? -1.0 : 1.0, 0);
    core::Mat3 R;
    R.col(0) = x;
    R.col(1) = z.cross(x);
    R.col(2) = z;
    Pose& palm = palms[static_cast<size_t>(side)];
    palm.rotation = core::Quat(R);
    palm.translation = Vec3(0, 0, -skeleton.palm_distance);
  }
  return palms;
}

// Default hold pose in the palm frame for a hand posed at X_W_palm in a person facing `yaw`:
// the object upright (yawed with the person), its centre just off the palm along the palm
// normal (outside the hand capsule).
Pose palm_hold(const human::Skeleton& skeleton, const Pose& X_W_palm, double yaw,
               const Vec3& half) {
  const double hand_radius = 0.035 * skeleton.scale;
  const Vec3 normal = X_W_palm.rotation * Vec3::UnitZ();
  Pose X_WO;
  X_WO.rotation = core::axis_angle(Vec3::UnitZ(), yaw);
  X_WO.translation = X_W_palm.translation + normal * (hand_radius + half.y() + 0.004) -
                     Vec3(0, 0, half.z());
  return X_W_palm.inverse() * X_WO;
}

struct Generated {
  Resolved resolved;
  std::string xml;
  human::Skeleton skeleton;
  std::vector<human::BodyCapsule> capsules;
  human::SkeletonPose human_start;
  std::array<Pose, 2> X_wrist_palm;
  std::vector<Pose> X_W_start;
  std::vector<Pose> X_palm_hold;
};

// The scene's <size> element with this arena (constraint rows, contacts).
std::string size_element(int njmax, int nconmax) {
  return fmt::format(R"(<size njmax="{}" nconmax="{}" nuserdata="{}"/>)", njmax, nconmax, kHandShapeValues);
}

Generated generate(const SceneSpec& spec) {
  Generated g{resolve(spec), {}, {}, {}, {}, {}, {}, {}};
  const SceneSpec& s = g.resolved.spec;
  const HumanSpec& h = s.human;
  std::array<Pose, human::kNumJoints> X_WJ{};
  if (h.present) {
    g.skeleton = human::Skeleton::FromHeight(h.height);
    g.capsules = human::body_capsules(g.skeleton);
    g.human_start = human::SkeletonPose::Standing(g.skeleton, h.x, h.y, h.yaw);
    // A hand holding an object from the start carries it in front: forearm forward.
    for (const ObjectSpec& o : s.objects)
      if (o.held_by)
        g.human_start.local[static_cast<size_t>(human::index(human::elbow(*o.held_by)))] =
            core::axis_angle(Vec3::UnitY(), -core::kPi / 2);
    g.X_wrist_palm = palm_frames(g.skeleton);
    X_WJ = human::forward_kinematics(g.skeleton, g.human_start);
  }

  std::string defaults, world, tendon, equality, actuator, contact;
  const double li = s.light_intensity;
  const std::string shadow = s.shadows ? "true" : "false";
  // Lights, floor, table. The floor's third size is only how MuJoCo draws it (a grid of quads
  // 2 x 0.25 m apart, the checker's squares): the 0.05 m grid it had cost a quarter of each
  // llvmpipe frame and changed no pixel under these lights (docs/rendering.md "Shapes").
  world += fmt::format(
      R"(<light name="top" directional="true" pos="0.5 0 3" dir="0 0 -1" diffuse="{0} {0} {0}" specular="0.1 0.1 0.1" castshadow="{2}"/>
<light name="fill" directional="true" pos="-1 -1 2.5" dir="0.4 0.4 -0.8" diffuse="{1} {1} {1}" specular="0 0 0" castshadow="false"/>
<geom name="floor" class="static" type="plane" size="4 4 0.25" material="floor"/>
<geom name="table" class="static" type="box" pos="{3}" size="{4}" rgba="0.72 0.58 0.42 1"/>
)",
      mjcf::num(0.6 * li), mjcf::num(0.3 * li), shadow,
      mjcf::vec(Vec3((kTableXMin + kTableXMax) / 2, 0, kTableTopZ - 0.025)),
      mjcf::vec(Vec3((kTableXMax - kTableXMin) / 2, kTableWidth / 2, 0.025)));
  for (int i = 0; i < 4; ++i) {
    const double x = i % 2 == 0 ? kTableXMin + 0.05 : kTableXMax - 0.05;
    const double y = i < 2 ? kTableWidth / 2 - 0.05 : -kTableWidth / 2 + 0.05;
    world += fmt::format(
        R"(<geom name="table_leg{}" class="static" type="box" pos="{}" size="0.03 0.03 {}" rgba="0.45 0.35 0.25 1"/>)",
        i, mjcf::vec(Vec3(x, y, (kTableTopZ - 0.05) / 2)), mjcf::num((kTableTopZ - 0.05) / 2));
    world += "\n";
  }
  for (const PlatformSpec& pl : s.platforms) {
    world += fmt::format(
        R"(<geom name="platform_{}" class="static" type="box" pos="{}" quat="{}" size="{}" rgba="0.55 0.45 0.35 1"/>)",
        pl.name, mjcf::vec(Vec3(pl.x, pl.y, kTableTopZ + pl.height / 2)),
        mjcf::quat(core::axis_angle(Vec3::UnitZ(), pl.yaw)),
        mjcf::vec(Vec3(pl.length / 2, pl.width / 2, pl.height / 2)));
    world += "\n";
  }
  // agentview (issue 16, docs/rendering.md): behind the robot's right shoulder and above it,
  // facing the person, as on a collaborative cell; at 224 x 224 px it holds the whole shared
  // workspace (x 0.15-0.85 m, y +-0.45 m on the table) and the upper body and hands of every
  // person the scripts draw (up to 1.95 m tall, standing at x 1.20-1.35 m, y -0.34..0.10 m).
  const Vec3 cam(-0.4, -1.4, 2.0);
  world += fmt::format(R"(<camera name="agentview" pos="{}" xyaxes="{}" fovy="54"/>)",
                       mjcf::vec(cam), mjcf::camera_xyaxes(cam, Vec3(0.62, 0, 1.2)));
  world += "\n";

  const Robot& robot = robot_by_name(s.robot);
  mjcf::robot(robot, Vec3(0, 0, kTableTopZ), defaults, world, tendon, equality, actuator);

  // Objects (on the table, or in a hand).
  for (size_t i = 0; i < s.objects.size(); ++i) {
    const ObjectSpec& o = s.objects[i];
    const Vec3& half = g.resolved.half_extents[i];
    Pose X_WO;
    Pose hold;
    if (h.present) {
      const auto side = o.held_by.value_or(h.handedness);
      const Pose X_W_palm = X_WJ[static_cast<size_t>(human::index(human::wrist(side)))] *
                            g.X_wrist_palm[static_cast<size_t>(side)];
      hold = palm_hold(g.skeleton, X_W_palm, h.yaw, half);
      if (o.held_by) X_WO = X_W_palm * hold;
    }
    if (!o.held_by) {
      X_WO.rotation = core::axis_angle(Vec3::UnitZ(), o.yaw);
      X_WO.translation = Vec3(o.x, o.y, g.resolved.bottom_z[i]);
    }
    g.X_W_start.push_back(X_WO);
    g.X_palm_hold.push_back(hold);
    mjcf::object(o, g.resolved.kinds[i], g.resolved.colours[i], X_WO, s.base_feet, world);
    // Human hands pass through objects (a held object sits against the palm); other human
    // parts collide with objects.
    if (h.present) {
      for (const auto side : {human::Side::kLeft, human::Side::kRight}) {
        const auto wrist = human::joint_name(human::wrist(side));
        contact += fmt::format(R"(<exclude body1="human_{}" body2="object_{}"/>)", wrist, o.name);
        if (g.resolved.kinds[i] == ObjectKind::kBox)
          contact += fmt::format(R"(<exclude body1="human_{}" body2="object_{}_lid"/>)", wrist,
                                 o.name);
        contact += "\n";
      }
    }
  }
  if (h.present) mjcf::human_body(g.skeleton, g.capsules, g.human_start, g.X_wrist_palm, world);

  // Home keyframe: arm home, fingers open, objects and human at their start poses.
  std::string key_qpos;
  for (const ArmJoint& j : robot.joints) key_qpos += mjcf::num(j.home) + " ";
  key_qpos += mjcf::num(robot.gripper.finger_travel) + " " + mjcf::num(robot.gripper.finger_travel);
  for (size_t i = 0; i < s.objects.size(); ++i) {
    key_qpos += " " + mjcf::vec(g.X_W_start[i].translation) + " " +
                mjcf::quat(g.X_W_start[i].rotation);
    if (g.resolved.kinds[i] == ObjectKind::kBox) key_qpos += " 0";
  }
  std::string key_ctrl;
  for (const ArmJoint& j : robot.joints) key_ctrl += mjcf::num(j.home) + " ";
  key_ctrl += mjcf::num(robot.gripper.max_width());
  std::string key_mocap;
  if (h.present) {
    std::string mpos, mquat;
    for (const Pose& X : X_WJ) {
      mpos += mjcf::vec(X.translation) + " ";
      mquat += mjcf::quat(X.rotation) + " ";
    }
    mpos.pop_back();  // MuJoCo counts a trailing space as one more number
    mquat.pop_back();
    key_mocap = fmt::format(R"( mpos="{}" mquat="{}")", mpos, mquat);
  }
  // The person's height, from which renderers size the drawn hands (kHumanHeightNumeric).
  const std::string custom =
      h.present ? fmt::format(R"(<custom><numeric name="{}" data="{}"/></custom>)" "\n", kHumanHeightNumeric,
                              mjcf::num(g.skeleton.height))
                : "";

  const int static_aff = mjcf::kBitRobot | mjcf::kBitObject;
  const int object_aff = mjcf::kBitStatic | mjcf::kBitRobot | mjcf::kBitObject | mjcf::kBitHuman;
  const int human_aff = mjcf::kBitRobot | mjcf::kBitObject;
  g.xml = fmt::format(
      R"(<mujoco model="hribench">
<compiler angle="radian" autolimits="true"/>
<option timestep="{timestep}" integrator="Euler" cone="elliptic" impratio="10" tolerance="1e-8" iterations="50"/>
{size}
{custom}<visual>
  <headlight ambient="0.35 0.35 0.35" diffuse="0.35 0.35 0.35" specular="0 0 0"/>
  <global offwidth="1280" offheight="960"/>
  <quality shadowsize="2048"/>
</visual>
<asset>
  <texture name="floor" type="2d" builtin="checker" rgb1="0.55 0.55 0.55" rgb2="0.45 0.45 0.45" width="256" height="256"/>
  <material name="floor" texture="floor" texrepeat="8 8"/>
</asset>
<default>
  <default class="static"><geom contype="{static_bit}" conaffinity="{static_aff}" condim="3" friction="0.8 0.005 0.0001"/></default>
  <default class="object"><geom contype="{object_bit}" conaffinity="{object_aff}" condim="4" friction="1.0 0.01 0.0001" solref="0.01 1" solimp="0.95 0.99 0.001"/></default>
  <default class="human"><geom contype="{human_bit}" conaffinity="{human_aff}" condim="3" friction="0.8 0.005 0.0001" density="1000"/></default>
{defaults}</default>
<worldbody>
{world}</worldbody>
<contact>
{contact}</contact>
<tendon>
{tendon}</tendon>
<equality>
{equality}</equality>
<actuator>
{actuator}</actuator>
<keyframe>
  <key name="home" qpos="{key_qpos}" ctrl="{key_ctrl}"{key_mocap}/>
</keyframe>
</mujoco>
)",
      fmt::arg("timestep", mjcf::num(kTimestep)),
      fmt::arg("size", size_element(kMaxConstraintRows, kMaxContacts)), fmt::arg("custom", custom),
      fmt::arg("static_bit", mjcf::kBitStatic),
      fmt::arg("static_aff", static_aff), fmt::arg("object_bit", mjcf::kBitObject),
      fmt::arg("object_aff", object_aff), fmt::arg("human_bit", mjcf::kBitHuman),
      fmt::arg("human_aff", human_aff), fmt::arg("defaults", defaults), fmt::arg("world", world),
      fmt::arg("contact", contact), fmt::arg("tendon", tendon), fmt::arg("equality", equality),
      fmt::arg("actuator", actuator), fmt::arg("key_qpos", key_qpos),
      fmt::arg("key_ctrl", key_ctrl), fmt::arg("key_mocap", key_mocap));
  return g;
}

// Compiles MJCF text through a VFS; throws InputError carrying MuJoCo's message on failure.
mjModel* compile(const std::string& xml) {
  // make_unique_for_overwrite: mj_defaultVFS clears the 2 MB struct itself.
  auto vfs = std::make_unique_for_overwrite<mjVFS>();
  mj_defaultVFS(vfs.get());
  constexpr const char* kName = "hribench_scene.xml";
  HRIB_CHECK(mj_makeEmptyFileVFS(vfs.get(), kName, static_cast<int>(xml.size())) == 0);
  const int index = mj_findFileVFS(vfs.get(), kName);
  HRIB_CHECK(index >= 0);
  std::memcpy(vfs->filedata[index], xml.data(), xml.size());
  std::array<char, 1024> error{};
  mjModel* m = mj_loadXML(kName, vfs.get(), error.data(), static_cast<int>(error.size()));
  mj_deleteVFS(vfs.get());
  if (m == nullptr)
    throw core::InputError::Message("model::build", std::string("MuJoCo rejected the scene: ") +
                                                        error.data());
  return m;
}

// Loads MJCF text through a VFS; throws InputError carrying MuJoCo's message on failure.
//
// MuJoCo 2.2.2's compiler makes an mjData of the model it compiles and clears its buffer, whose
// constraint arrays (efc_AR alone is njmax x njmax) are most of it: about 4 ms of every episode
// for an arena nothing compiled uses (docs/performance.md, "Fixed costs per episode"). So the
// scene is compiled with an empty arena and the arena's sizes are set in the compiled model
// afterwards, the stack as MuJoCo's compiler sizes it for them (user_model.cc: the larger of
// 1,000 and five times the square of njmax + neq + nv, plus twenty per model element).
// ModelTest.TheArenaSetAfterCompilingGivesTheSameModel holds the result, byte for byte, to the
// scene compiled with its arena.
mjModel* load(const std::string& xml) {
  const std::string sized = size_element(kMaxConstraintRows, kMaxContacts);
  const size_t at = xml.find(sized);
  HRIB_CHECK(at != std::string::npos) << "the scene has no " << sized;
  std::string empty_arena = xml;
  empty_arena.replace(at, sized.size(), size_element(0, 0));
  mjModel* m = compile(empty_arena);
  m->njmax = kMaxConstraintRows;
  m->nconmax = kMaxContacts;
  const int rows = m->njmax + m->neq + m->nv;
  const int elements = m->nq + m->nv + m->nu + m->na + m->nbody + m->njnt + m->ngeom + m->nsite +
                       m->neq + m->ntendon + m->nwrap;
  m->nstack = std::max(1000, 5 * rows * rows + 20 * elements);
  return m;
}

int id_of(const mjModel* m, mjtObj type, const std::string& name) {
  const int id = mj_name2id(m, type, name.c_str());
  HRIB_CHECK(id >= 0) << "no MuJoCo object named " << name;
  return id;
}

}  // namespace

std::string_view to_string(ObjectKind kind) { return script::catalogue_kinds()[static_cast<size_t>(kind)].name; }

std::optional<ObjectKind> object_kind_from_name(std::string_view name) {
  const auto& kinds = script::catalogue_kinds();
  for (size_t i = 0; i < kinds.size(); ++i)
    if (kinds[i].name == name) return static_cast<ObjectKind>(i);
  return std::nullopt;
}

std::optional<Rgba> colour_from_name(std::string_view name) {
  // (Also "grey", the old spelling of gray: eval's script driver still passes it.)
  const script::ColourEntry* c = script::find_colour(name == "grey" ? "gray" : name);
  if (!c) return std::nullopt;
  return Rgba{c->rgba[0], c->rgba[1], c->rgba[2], c->rgba[3]};
}

const std::vector<std::string_view>& colour_names() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> v;
    for (const script::ColourEntry& c : script::catalogue_colours()) v.push_back(c.name);
    return v;
  }();
  return names;
}

std::string_view to_string(GeomOwner owner) {
  switch (owner) {
    case GeomOwner::kOther: return "other";
    case GeomOwner::kFloor: return "floor";
    case GeomOwner::kTable: return "table";
    case GeomOwner::kRobotLink: return "robot_link";
    case GeomOwner::kRobotHand: return "robot_hand";
    case GeomOwner::kRobotFinger: return "robot_finger";
    case GeomOwner::kHuman: return "human";
    case GeomOwner::kObject: return "object";
    case GeomOwner::kPlatform: return "platform";
  }
  return "other";
}

SceneSpec SceneSpec::Default() {
  SceneSpec s;
  ObjectSpec cube;
  cube.kind = "cube";
  cube.name = "cube";
  cube.colour = "red";
  cube.x = 0.5;
  cube.y = 0.0;
  ObjectSpec cup;
  cup.kind = "cup";
  cup.name = "cup";
  cup.colour = "green";
  cup.x = 0.45;
  cup.y = 0.25;
  ObjectSpec bin;
  bin.kind = "bin";
  bin.name = "bin";
  bin.colour = "blue";
  bin.x = 0.45;
  bin.y = -0.3;
  s.objects = {cube, cup, bin};
  return s;
}

int Model::platform_index(std::string_view name) const {
  for (size_t i = 0; i < platforms.size(); ++i)
    if (platforms[i].name == name) return static_cast<int>(i);
  return -1;
}

double container_floor_height(ObjectKind kind, double size_scale) {
  const auto walls = mjcf::container_walls(kind, size_scale);
  return walls ? walls->thickness : 0.0;
}

int Model::object_index(std::string_view name) const {
  for (size_t i = 0; i < objects.size(); ++i)
    if (objects[i].name == name) return static_cast<int>(i);
  return -1;
}

std::string to_mjcf(const SceneSpec& spec) { return generate(spec).xml; }

Model build(const SceneSpec& spec) {
  Generated g = generate(spec);
  Model model;
  model.mj.reset(load(g.xml));
  const mjModel* m = model.m();
  model.spec = std::move(g.resolved.spec);
  model.mjcf = std::move(g.xml);

  // Robot.
  model.robot = robot_by_name(model.spec.robot);
  for (const ArmJoint& j : model.robot.joints) {
    const int joint = id_of(m, mjOBJ_JOINT, j.name);
    model.arm_joint.push_back(joint);
    model.arm_qpos_adr.push_back(m->jnt_qposadr[joint]);
    model.arm_dof_adr.push_back(m->jnt_dofadr[joint]);
    model.arm_actuator.push_back(id_of(m, mjOBJ_ACTUATOR, j.actuator));
  }
  for (const Link& link : model.robot.links) model.link_body.push_back(id_of(m, mjOBJ_BODY, link.name));
  const std::array<std::string, 2> finger_joints = {"finger_joint1", "finger_joint2"};
  const std::array<std::string, 2> finger_bodies = {"left_finger", "right_finger"};
  for (size_t i = 0; i < 2; ++i) {
    model.finger_joint[i] = id_of(m, mjOBJ_JOINT, finger_joints[i]);
    model.finger_qpos_adr[i] = m->jnt_qposadr[model.finger_joint[i]];
    model.finger_dof_adr[i] = m->jnt_dofadr[model.finger_joint[i]];
    model.finger_body[i] = id_of(m, mjOBJ_BODY, finger_bodies[i]);
  }
  model.gripper_actuator = id_of(m, mjOBJ_ACTUATOR, "gripper");
  model.hand_body = id_of(m, mjOBJ_BODY, "hand");
  model.flange_site = id_of(m, mjOBJ_SITE, "flange");
  model.tcp_site = id_of(m, mjOBJ_SITE, "tcp");
  model.X_WB.translation = Vec3(0, 0, kTableTopZ);
  model.agentview_camera = id_of(m, mjOBJ_CAMERA, "agentview");
  model.wrist_camera = id_of(m, mjOBJ_CAMERA, model.robot.wrist_camera.name);
  model.table_geom = id_of(m, mjOBJ_GEOM, "table");
  model.floor_geom = id_of(m, mjOBJ_GEOM, "floor");
  for (const PlatformSpec& pl : model.spec.platforms) {
    PlatformInfo info;
    info.name = pl.name;
    info.geom = id_of(m, mjOBJ_GEOM, "platform_" + pl.name);
    info.X_WC.rotation = core::axis_angle(Vec3::UnitZ(), pl.yaw);
    info.X_WC.translation = Vec3(pl.x, pl.y, kTableTopZ + pl.height / 2);
    info.half_extents = Vec3(pl.length / 2, pl.width / 2, pl.height / 2);
    model.platforms.push_back(std::move(info));
  }

  // Human.
  model.human_body.fill(-1);
  model.human_mocap.fill(-1);
  model.has_human = model.spec.human.present;
  if (model.has_human) {
    model.skeleton = g.skeleton;
    model.human_capsules = g.capsules;
    model.human_start = g.human_start;
    model.X_wrist_palm = g.X_wrist_palm;
    for (int j = 0; j < human::kNumJoints; ++j) {
      const auto k = static_cast<size_t>(j);
      const int body = id_of(
          m, mjOBJ_BODY,
          "human_" + std::string(human::joint_name(static_cast<human::Joint>(j))));
      model.human_body[k] = body;
      model.human_mocap[k] = m->body_mocapid[body];
    }
    for (const auto& c : model.human_capsules)
      model.human_capsule_geom.push_back(id_of(m, mjOBJ_GEOM, "human_" + std::string(c.name)));
  }

  // Objects.
  for (size_t i = 0; i < model.spec.objects.size(); ++i) {
    const ObjectSpec& o = model.spec.objects[i];
    ObjectInfo info;
    info.name = o.name;
    info.kind = g.resolved.kinds[i];
    info.rgba = g.resolved.colours[i];
    info.body = id_of(m, mjOBJ_BODY, "object_" + o.name);
    const int joint = m->body_jntadr[info.body];
    info.qpos_adr = m->jnt_qposadr[joint];
    info.dof_adr = m->jnt_dofadr[joint];
    info.mass = m->body_subtreemass[info.body];
    info.half_extents = g.resolved.half_extents[i];
    info.X_W_start = g.X_W_start[i];
    info.X_palm_hold = g.X_palm_hold[i];
    info.held_by = o.held_by;
    if (info.kind == ObjectKind::kBox) {
      info.lid_body = id_of(m, mjOBJ_BODY, "object_" + o.name + "_lid");
      info.lid_joint = id_of(m, mjOBJ_JOINT, "object_" + o.name + "_lid_hinge");
    }
    model.objects.push_back(std::move(info));
  }

  // Geom tags, from the owning body.
  std::map<int, GeomTag> by_body;
  for (size_t k = 0; k < model.link_body.size(); ++k)
    by_body[model.link_body[k]] = {GeomOwner::kRobotLink, static_cast<int>(k)};
  by_body[model.hand_body] = {GeomOwner::kRobotHand, -1};
  for (size_t k = 0; k < 2; ++k)
    by_body[model.finger_body[k]] = {GeomOwner::kRobotFinger, static_cast<int>(k)};
  for (size_t k = 0; k < model.objects.size(); ++k) {
    by_body[model.objects[k].body] = {GeomOwner::kObject, static_cast<int>(k)};
    if (model.objects[k].lid_body >= 0)
      by_body[model.objects[k].lid_body] = {GeomOwner::kObject, static_cast<int>(k)};
  }
  model.geom_tags.assign(static_cast<size_t>(m->ngeom), GeomTag{});
  for (int gid = 0; gid < m->ngeom; ++gid) {
    const auto it = by_body.find(m->geom_bodyid[gid]);
    if (it != by_body.end()) model.geom_tags[static_cast<size_t>(gid)] = it->second;
  }
  for (size_t c = 0; c < model.human_capsule_geom.size(); ++c) {
    GeomTag& tag = model.geom_tags[static_cast<size_t>(model.human_capsule_geom[c])];
    tag = {GeomOwner::kHuman, static_cast<int>(c), model.human_capsules[c].region,
           model.human_capsules[c].joint};
  }
  model.geom_tags[static_cast<size_t>(model.floor_geom)].owner = GeomOwner::kFloor;
  for (size_t k = 0; k < model.platforms.size(); ++k)
    model.geom_tags[static_cast<size_t>(model.platforms[k].geom)] = {GeomOwner::kPlatform, static_cast<int>(k)};
  for (int gid = 0; gid < m->ngeom; ++gid) {
    const char* name = mj_id2name(m, mjOBJ_GEOM, gid);
    if (name != nullptr && std::strncmp(name, "table", 5) == 0)
      model.geom_tags[static_cast<size_t>(gid)].owner = GeomOwner::kTable;
  }
  servo_damping_in_joints(model);
  return model;
}

double servo_kv(const mjModel& m, int actuator) { return -m.actuator_biasprm[actuator * mjNBIAS + 2]; }

void servo_damping_in_joints(Model& model) {
  mjModel* m = model.mj.get();
  for (size_t j = 0; j < model.arm_actuator.size(); ++j) {
    m->dof_damping[model.arm_dof_adr[j]] += servo_kv(*m, model.arm_actuator[j]);
  }
  model.servo_damping_in_joints = true;
}

void servo_damping_in_servos(Model& model) {
  mjModel* m = model.mj.get();
  for (size_t j = 0; j < model.arm_actuator.size(); ++j) m->dof_damping[model.arm_dof_adr[j]] = model.robot.joints[j].damping;
  model.servo_damping_in_joints = false;
}

}  // namespace hribench::model
