#include "human/retarget.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "core/errors.h"

namespace hribench::human {
namespace {

using core::Quat;
using core::Vec3;

constexpr double kTiny = 1e-9;

size_t u(Joint j) { return static_cast<size_t>(index(j)); }

// Orthonormal frame (columns) from a primary and a secondary direction; nullopt if degenerate.
std::optional<core::Mat3> frame_of(const Vec3& primary, const Vec3& secondary) {
  const double n1 = primary.norm();
  if (n1 < kTiny) return std::nullopt;
  const Vec3 e1 = primary / n1;
  const Vec3 s = secondary - secondary.dot(e1) * e1;
  if (s.norm() < 1e-6 * std::max(secondary.norm(), kTiny) || s.norm() < kTiny) return std::nullopt;
  const Vec3 e2 = s.normalized();
  core::Mat3 F;
  F.col(0) = e1;
  F.col(1) = e2;
  F.col(2) = e1.cross(e2);
  return F;
}

// The smallest rotation taking the direction `from` to `to`, applied after `base`.
Quat swing(const Quat& base, const Vec3& rest_dir, const Vec3& target) {
  if (target.norm() < kTiny || rest_dir.norm() < kTiny) return base;
  const Vec3 from = base * rest_dir;
  return (Quat::FromTwoVectors(from, target) * base).normalized();
}

// World rotation of a joint with a primary child direction and a secondary line, falling back
// to a swing from `base` when the secondary line is degenerate.
Quat align(const Quat& base, const Vec3& rest_primary, const Vec3& rest_secondary,
           const Vec3& target_primary, const Vec3& target_secondary) {
  const auto rest = frame_of(rest_primary, rest_secondary);
  const auto target = frame_of(target_primary, target_secondary);
  if (!rest || !target) return swing(base, rest_primary, target_primary);
  return Quat(core::Mat3(*target * rest->transpose())).normalized();
}

// Marker helpers for the conventions table.
using Marker = std::vector<std::pair<std::string, double>>;
Marker one(std::string name) { return {{std::move(name), 1.0}}; }
Marker mix(std::string a, double wa, std::string b) { return {{std::move(a), wa}, {std::move(b), 1.0 - wa}}; }

// One side's limb joint names.
struct SideNames {
  std::string hip, knee, ankle, foot, shoulder, elbow, wrist;
  std::vector<std::string> hand_tip;
};

// Both sides' names: "left"/"right" + each suffix; in hand-tip patterns "{w}" is left/right and
// "{s}" is l/r.
std::array<SideNames, 2> sides(const std::array<std::string, 7>& suffix, const std::vector<std::string>& tips) {
  std::array<SideNames, 2> out;
  for (size_t s = 0; s < 2; ++s) {
    const std::string w = s == 0 ? "left" : "right";
    const std::string l = s == 0 ? "l" : "r";
    out[s] = {w + suffix[0], w + suffix[1], w + suffix[2], w + suffix[3], w + suffix[4], w + suffix[5], w + suffix[6], {}};
    for (std::string tip : tips) {
      for (const auto& [key, value] : {std::pair<std::string, std::string>{"{w}", w}, {"{s}", l}}) {
        const size_t at = tip.find(key);
        if (at != std::string::npos) tip.replace(at, key.size(), value);
      }
      out[s].hand_tip.push_back(tip);
    }
  }
  return out;
}

NameConvention make(std::string name, Marker pelvis, Marker spine1, Marker spine2, Marker spine3,
                    Marker neck, Marker head, const std::array<SideNames, 2>& side,
                    const std::array<Marker, 2>& collar) {
  NameConvention c;
  c.name = std::move(name);
  c.joint[u(Joint::kPelvis)] = std::move(pelvis);
  c.joint[u(Joint::kSpine1)] = std::move(spine1);
  c.joint[u(Joint::kSpine2)] = std::move(spine2);
  c.joint[u(Joint::kSpine3)] = std::move(spine3);
  c.joint[u(Joint::kNeck)] = std::move(neck);
  c.joint[u(Joint::kHead)] = std::move(head);
  for (size_t s = 0; s < 2; ++s) {
    const bool left = s == 0;
    c.joint[u(left ? Joint::kLeftHip : Joint::kRightHip)] = one(side[s].hip);
    c.joint[u(left ? Joint::kLeftKnee : Joint::kRightKnee)] = one(side[s].knee);
    c.joint[u(left ? Joint::kLeftAnkle : Joint::kRightAnkle)] = one(side[s].ankle);
    c.joint[u(left ? Joint::kLeftFoot : Joint::kRightFoot)] = one(side[s].foot);
    c.joint[u(left ? Joint::kLeftCollar : Joint::kRightCollar)] = collar[s];
    c.joint[u(left ? Joint::kLeftShoulder : Joint::kRightShoulder)] = one(side[s].shoulder);
    c.joint[u(left ? Joint::kLeftElbow : Joint::kRightElbow)] = one(side[s].elbow);
    c.joint[u(left ? Joint::kLeftWrist : Joint::kRightWrist)] = one(side[s].wrist);
    c.hand_tip[s] = side[s].hand_tip;
  }
  return c;
}

std::vector<NameConvention> build_conventions() {
  std::vector<NameConvention> all;
  // SMPL / HumanML3D names (ours): pelvis, left_hip, ...; "_end" are our BVH End Sites.
  {
    NameConvention c;
    c.name = "smpl";
    for (int j = 0; j < kNumJoints; ++j) {
      c.joint[static_cast<size_t>(j)] = one(normalize_joint_name(joint_name(static_cast<Joint>(j))));
    }
    c.hand_tip = {std::vector<std::string>{"leftwristend", "lefthand"},
                  std::vector<std::string>{"rightwristend", "righthand"}};
    all.push_back(std::move(c));
  }
  // SMPL short names (HY-Motion joint_names.json, PHC): Pelvis, L_Hip, ..., R_Wrist.
  {
    const std::array<std::string_view, kNumJoints> names = {
        "pelvis", "lhip",   "rhip",    "spine1",    "lknee",     "rknee",  "spine2", "lankle",
        "rankle", "spine3", "lfoot",   "rfoot",     "neck",      "lcollar", "rcollar", "head",
        "lshoulder", "rshoulder", "lelbow", "relbow", "lwrist", "rwrist"};
    NameConvention c;
    c.name = "smpl_short";
    for (size_t j = 0; j < names.size(); ++j) c.joint[j] = one(std::string(names[j]));
    c.hand_tip = {std::vector<std::string>{"lhand", "lwristend"},
                  std::vector<std::string>{"rhand", "rwristend"}};
    all.push_back(std::move(c));
  }
  // Mixamo: Hips, Spine, Spine1, Spine2, Neck, Head, LeftShoulder (clavicle), LeftArm, ...
  {
    const auto side = sides({"upleg", "leg", "foot", "toebase", "arm", "forearm", "hand"},
                            {"{w}handmiddle1", "{w}handindex1", "{w}handend"});
    all.push_back(make("mixamo", one("hips"), one("spine"), one("spine1"), one("spine2"),
                       one("neck"), one("head"), side,
                       {one("leftshoulder"), one("rightshoulder")}));
  }
  // CMU, MotionBuilder-friendly cgspeed release: Hips, LHipJoint, LeftUpLeg, ..., LowerBack,
  // Spine, Spine1, Neck, Neck1, Head, LeftShoulder (clavicle), LeftArm, LeftForeArm, LeftHand.
  {
    const auto side = sides({"upleg", "leg", "foot", "toebase", "arm", "forearm", "hand"},
                            {"{w}fingerbase", "{w}handindex1"});
    all.push_back(make("cmu_motionbuilder", one("hips"), one("spine"), mix("spine", 0.3, "spine1"),
                       one("spine1"), one("neck1"), one("head"), side,
                       {mix("spine1", 0.5, "leftarm"), mix("spine1", 0.5, "rightarm")}));
  }
  // CMU, 3ds-Max-friendly cgspeed release (data/motion/cmu_131_01.bvh): Hips, LHipJoint,
  // LeftHip, LeftKnee, LeftAnkle, LeftToe, lowerback, Chest, Chest2, lowerneck, Neck, Head,
  // LeftCollar, LeftShoulder (the shoulder joint), LeftElbow, LeftWrist, lhand.
  {
    const auto side = sides({"hip", "knee", "ankle", "toe", "shoulder", "elbow", "wrist"},
                            {"{s}hand", "{s}fingers"});
    all.push_back(make("cmu", one("hips"), one("chest"), mix("chest", 0.3, "chest2"),
                       one("chest2"), one("neck"), one("head"), side,
                       {mix("chest2", 0.5, "leftshoulder"), mix("chest2", 0.5, "rightshoulder")}));
  }
  return all;
}

}  // namespace

core::Mat3 y_up_to_z_up() {
  core::Mat3 M;
  M << 0, 0, 1,
       1, 0, 0,
       0, 1, 0;
  return M;
}

RestTree rest_tree(const Skeleton& skeleton) {
  RestTree t;
  t.offset = skeleton.offset;
  t.hand_dir = {Vec3(0, 0, -1), Vec3(0, 0, -1)};
  return t;
}

std::array<Quat, kNumJoints> solve_world_rotations(const RestTree& tree, const JointTargets& targets) {
  const auto& o = tree.offset;
  const auto& p = targets.joint;
  std::array<Quat, kNumJoints> R;
  R.fill(Quat::Identity());
  // Pelvis: spine1 exact, the hip line as close as possible.
  R[0] = align(Quat::Identity(), o[u(Joint::kSpine1)], o[u(Joint::kLeftHip)] - o[u(Joint::kRightHip)],
               p[u(Joint::kSpine1)] - p[0], p[u(Joint::kLeftHip)] - p[u(Joint::kRightHip)]);
  // Children of each joint (SMPL order: parents first).
  std::array<std::vector<size_t>, kNumJoints> children;
  for (int j = 1; j < kNumJoints; ++j) children[u(*parent(static_cast<Joint>(j)))].push_back(static_cast<size_t>(j));
  for (int jj = 1; jj < kNumJoints; ++jj) {
    const auto joint = static_cast<Joint>(jj);
    const size_t j = u(joint);
    const Quat& base = R[u(*parent(joint))];
    if (joint == Joint::kSpine3) {
      // Neck exact, the collar line as close as possible.
      const Vec3 rest_line = o[u(Joint::kLeftCollar)] - o[u(Joint::kRightCollar)];
      const Vec3 rest_primary = base * o[u(Joint::kNeck)];
      R[j] = align(Quat::Identity(), rest_primary, base * rest_line, p[u(Joint::kNeck)] - p[j],
                   p[u(Joint::kLeftCollar)] - p[u(Joint::kRightCollar)]) * base;
      R[j].normalize();
    } else if (children[j].size() == 1) {
      const size_t c = children[j][0];
      R[j] = swing(base, o[c], p[c] - p[j]);
    } else if (joint == Joint::kLeftWrist || joint == Joint::kRightWrist) {
      const size_t s = joint == Joint::kLeftWrist ? 0 : 1;
      R[j] = targets.hand_tip[s] ? swing(base, tree.hand_dir[s], *targets.hand_tip[s] - p[j]) : base;
    } else {
      R[j] = base;
    }
  }
  return R;
}

std::string normalize_joint_name(std::string_view name) {
  const size_t colon = name.rfind(':');
  if (colon != std::string_view::npos) name.remove_prefix(colon + 1);
  std::string out;
  for (const char c : name) {
    if (c == '_' || c == '-' || c == ' ' || c == '.') continue;
    out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}

const std::vector<NameConvention>& name_conventions() {
  static const std::vector<NameConvention> all = build_conventions();
  return all;
}

namespace {
std::map<std::string, size_t> name_index(const std::vector<std::string>& names) {
  std::map<std::string, size_t> index_of;
  for (size_t i = 0; i < names.size(); ++i) index_of.emplace(normalize_joint_name(names[i]), i);
  return index_of;
}
}  // namespace

const NameConvention& match_convention(const std::vector<std::string>& names, std::string_view where) {
  const auto index_of = name_index(names);
  const NameConvention* closest = nullptr;
  std::vector<std::string> closest_missing;
  for (const NameConvention& c : name_conventions()) {
    std::vector<std::string> missing;
    for (const Marker& m : c.joint) {
      for (const auto& [name, w] : m) {
        if (!index_of.contains(name) &&
            std::find(missing.begin(), missing.end(), name) == missing.end()) {
          missing.push_back(name);
        }
      }
    }
    if (missing.empty()) return c;
    if (closest == nullptr || missing.size() < closest_missing.size()) {
      closest = &c;
      closest_missing = missing;
    }
  }
  std::string list;
  for (size_t i = 0; i < closest_missing.size() && i < 6; ++i) list += (i ? ", " : "") + closest_missing[i];
  if (closest_missing.size() > 6) list += ", ...";
  throw core::InputError(std::string(where),
                         "joint names of a known skeleton (smpl, smpl_short, mixamo, "
                         "cmu_motionbuilder, cmu)",
                         fmt::format("{} joints; closest is {}, missing {}", names.size(),
                                     closest->name, list));
}

JointTargets targets_from_named(const NameConvention& convention, const std::vector<std::string>& names,
                                const std::vector<Vec3>& positions) {
  HRIB_CHECK(names.size() == positions.size());
  const auto index_of = name_index(names);
  JointTargets t;
  for (size_t j = 0; j < t.joint.size(); ++j) {
    Vec3 sum = Vec3::Zero();
    for (const auto& [name, w] : convention.joint[j]) sum += w * positions[index_of.at(name)];
    t.joint[j] = sum;
  }
  for (size_t s = 0; s < 2; ++s) {
    for (const std::string& name : convention.hand_tip[s]) {
      const auto it = index_of.find(name);
      if (it == index_of.end()) continue;
      t.hand_tip[s] = positions[it->second];
      break;
    }
  }
  return t;
}

double leg_length(const JointTargets& t) {
  const auto& p = t.joint;
  const double left = (p[u(Joint::kLeftKnee)] - p[u(Joint::kLeftHip)]).norm() +
                      (p[u(Joint::kLeftAnkle)] - p[u(Joint::kLeftKnee)]).norm();
  const double right = (p[u(Joint::kRightKnee)] - p[u(Joint::kRightHip)]).norm() +
                       (p[u(Joint::kRightAnkle)] - p[u(Joint::kRightKnee)]).norm();
  return 0.5 * (left + right);
}

double leg_length(const Skeleton& k) {
  return 0.5 * (k.bone_length(Joint::kLeftKnee) + k.bone_length(Joint::kLeftAnkle) +
                k.bone_length(Joint::kRightKnee) + k.bone_length(Joint::kRightAnkle));
}

Clip clip_from_targets(const std::vector<JointTargets>& frames, double fps,
                       const RetargetOptions& options, std::string_view where) {
  const std::string w(where);
  if (frames.empty()) throw core::InputError(w, "at least one frame", "none");
  const double rate = options.fps.value_or(fps);
  if (!std::isfinite(rate) || rate <= 0 || rate > 1000) {
    throw core::InputError(w, "a frame rate in (0, 1000] fps", fmt::format("{}", rate));
  }
  for (size_t f = 0; f < frames.size(); ++f) {
    for (const Vec3& v : frames[f].joint) {
      if (!v.allFinite()) throw core::InputError(w, "finite joint positions", fmt::format("a NaN or infinity in frame {}", f));
    }
  }
  const double source_leg = leg_length(frames[0]);
  if (!(source_leg > 1e-6)) throw core::InputError(w, "a skeleton with legs (hip, knee, ankle apart)", "zero leg length in frame 0");
  double height = 0;
  if (options.height) {
    height = *options.height;
  } else {
    height = std::clamp(source_leg / leg_length(Skeleton::FromHeight(1.0)), 1.0, 2.5);
  }
  Clip clip;
  clip.skeleton = Skeleton::FromHeight(height);
  clip.fps = rate;
  const RestTree tree = rest_tree(clip.skeleton);
  const double root_scale = leg_length(clip.skeleton) / source_leg;
  clip.frames.reserve(frames.size());
  for (const JointTargets& t : frames) {
    const auto R = solve_world_rotations(tree, t);
    SkeletonPose pose;
    pose.X_WP = {R[0], t.joint[0] * root_scale};
    for (int j = 1; j < kNumJoints; ++j) {
      const auto uj = static_cast<size_t>(j);
      pose.local[uj] = (R[u(*parent(static_cast<Joint>(j)))].conjugate() * R[uj]).normalized();
    }
    clip.frames.push_back(pose);
  }
  if (options.ground.value_or(false)) {
    const Skeleton& k = clip.skeleton;
    const double ankle_height = k.pelvis_height + k.offset[u(Joint::kLeftHip)].z() +
                                k.offset[u(Joint::kLeftKnee)].z() + k.offset[u(Joint::kLeftAnkle)].z();
    double lowest = 1e300;
    for (const SkeletonPose& pose : clip.frames) {
      const auto X = forward_kinematics(k, pose);
      for (const Joint a : {Joint::kLeftAnkle, Joint::kRightAnkle}) {
        lowest = std::min(lowest, X[u(a)].translation.z() - ankle_height);
      }
    }
    for (SkeletonPose& pose : clip.frames) pose.X_WP.translation.z() -= lowest;
  }
  return clip;
}

Clip time_scale(const Clip& clip, double factor) {
  if (!std::isfinite(factor) || factor <= 0) {
    throw core::InputError("time_scale factor", "a positive finite number", fmt::format("{}", factor));
  }
  HRIB_CHECK(!clip.frames.empty());
  Clip out = clip;
  const double duration = clip.duration() * factor;
  const auto n = static_cast<size_t>(std::llround(duration * clip.fps)) + 1;
  out.frames.clear();
  out.frames.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    out.frames.push_back(clip.pose_at(static_cast<double>(i) / clip.fps / factor));
  }
  for (Phase& phase : out.phases) {
    phase.start *= factor;
    phase.end *= factor;
  }
  return out;
}

double facing_yaw(const SkeletonPose& pose) {
  const Vec3 x = pose.X_WP.rotation * Vec3::UnitX();
  return std::atan2(x.y(), x.x());
}

Clip place(const Clip& clip, double x, double y, double yaw_rad) {
  HRIB_CHECK(!clip.frames.empty());
  Clip out = clip;
  const Vec3 start = clip.frames[0].X_WP.translation;
  const Quat turn = core::axis_angle(Vec3::UnitZ(), yaw_rad - facing_yaw(clip.frames[0]));
  for (SkeletonPose& pose : out.frames) {
    const Vec3 rel = pose.X_WP.translation - Vec3(start.x(), start.y(), 0);
    pose.X_WP.translation = turn * rel + Vec3(x, y, 0);
    pose.X_WP.rotation = (turn * pose.X_WP.rotation).normalized();
  }
  return out;
}

}  // namespace hribench::human
