#include "human/smplh.h"

#include <cmath>

#include <fmt/format.h>

#include "core/errors.h"

namespace hribench::human {
namespace {

using core::Quat;
using core::Vec3;

size_t u(Joint j) { return static_cast<size_t>(index(j)); }

Quat from_axis_angle(const Vec3& v) {
  const double angle = v.norm();
  if (angle < 1e-12) return Quat::Identity();
  return Quat(Eigen::AngleAxisd(angle, v / angle));
}

Vec3 to_axis_angle(const Quat& q) {
  const Eigen::AngleAxisd aa(q.normalized());
  return aa.axis() * aa.angle();
}

// A numeric member with a finiteness check that names the byte offset of a bad value.
NpyArray finite_array(const NpzArchive& archive, std::string_view key, std::string_view where) {
  NpyArray a = archive.array(key);
  for (size_t i = 0; i < a.values.size(); ++i) {
    if (!std::isfinite(a.values[i])) {
      throw core::InputError(fmt::format("{}[{}.npy]: byte {}", where, key, a.data_offset + i * a.item_size),
                             "finite values", fmt::format("{} at index {}", a.values[i], i));
    }
  }
  return a;
}

// World pose of each SMPL joint (file frame) for one frame.
std::array<core::Pose, kNumJoints> smpl_fk(const std::array<Vec3, kNumJoints>& aa, const Vec3& trans) {
  const RestTree tree = smpl_rest_tree();
  std::array<core::Pose, kNumJoints> X;
  X[0] = {from_axis_angle(aa[0]), smpl_pelvis_rest() + trans};
  for (int j = 1; j < kNumJoints; ++j) {
    const auto uj = static_cast<size_t>(j);
    X[uj] = X[u(*parent(static_cast<Joint>(j)))] * core::Pose{from_axis_angle(aa[uj]), tree.offset[uj]};
  }
  return X;
}

// Offsets of the neutral SMPL body (PHC smpl_humanoid.xml body positions, SMPL frame).
constexpr std::array<std::array<double, 3>, kNumJoints> kSmplOffsets = {{
    {0, 0, 0},                       // pelvis
    {0.0695, -0.0914, -0.0068},      // left_hip
    {-0.0677, -0.0905, -0.0043},     // right_hip
    {-0.0025, 0.109, -0.0267},       // spine1
    {0.0343, -0.3752, -0.0045},      // left_knee
    {-0.0383, -0.3826, -0.0089},     // right_knee
    {0.0055, 0.1352, 0.0011},        // spine2
    {-0.0136, -0.398, -0.0437},      // left_ankle
    {0.0158, -0.3984, -0.0423},      // right_ankle
    {0.0015, 0.0529, 0.0254},        // spine3
    {0.0264, -0.0558, 0.1193},       // left_foot
    {-0.0254, -0.0481, 0.1233},      // right_foot
    {-0.0028, 0.2139, -0.0429},      // neck
    {0.0788, 0.1217, -0.0341},       // left_collar
    {-0.0818, 0.1188, -0.0386},      // right_collar
    {0.0052, 0.065, 0.0513},         // head
    {0.091, 0.0305, -0.0089},        // left_shoulder
    {-0.096, 0.0326, -0.0091},       // right_shoulder
    {0.2596, -0.0128, -0.0275},      // left_elbow
    {-0.2537, -0.0133, -0.0214},     // right_elbow
    {0.2492, 0.009, -0.0012},        // left_wrist
    {-0.2553, 0.0078, -0.0056},      // right_wrist
}};
const Vec3 kLeftHand(0.084, -0.0082, -0.0149);
const Vec3 kRightHand(-0.0846, -0.0061, -0.0103);

}  // namespace

RestTree smpl_rest_tree() {
  RestTree t;
  for (size_t j = 0; j < t.offset.size(); ++j) t.offset[j] = Vec3(kSmplOffsets[j][0], kSmplOffsets[j][1], kSmplOffsets[j][2]);
  t.hand_dir = {kLeftHand.normalized(), kRightHand.normalized()};
  return t;
}

Vec3 smpl_pelvis_rest() { return Vec3(-0.0018, -0.2233, 0.0282); }

JointTargets smpl_forward_kinematics(const std::array<Vec3, kNumJoints>& axis_angle, const Vec3& trans) {
  const auto X = smpl_fk(axis_angle, trans);
  JointTargets t;
  for (size_t j = 0; j < X.size(); ++j) t.joint[j] = X[j].translation;
  t.hand_tip[0] = X[u(Joint::kLeftWrist)] * kLeftHand;
  t.hand_tip[1] = X[u(Joint::kRightWrist)] * kRightHand;
  return t;
}

Clip clip_from_smplh(const NpzArchive& archive, const RetargetOptions& options, std::string_view where) {
  const NpyArray poses = finite_array(archive, "poses", where);
  const NpyArray trans = finite_array(archive, "trans", where);
  if (poses.shape.size() != 2 || poses.shape[1] < 66 || poses.shape[1] % 3 != 0 || poses.shape[0] == 0) {
    std::string shape;
    for (const size_t d : poses.shape) shape += fmt::format("{}{}", shape.empty() ? "" : ", ", d);
    throw core::InputError(fmt::format("{}[poses.npy]", where),
                           "shape (frames, 3 x joints) with at least 22 joints (156 for SMPL-H)",
                           fmt::format("({})", shape));
  }
  const size_t frames = poses.shape[0];
  if (trans.shape.size() != 2 || trans.shape[0] != frames || trans.shape[1] != 3) {
    std::string shape;
    for (const size_t d : trans.shape) shape += fmt::format("{}{}", shape.empty() ? "" : ", ", d);
    throw core::InputError(fmt::format("{}[trans.npy]", where), fmt::format("shape ({}, 3)", frames),
                           fmt::format("({})", shape));
  }
  double fps = 30;
  for (const std::string_view key : {"mocap_framerate", "mocap_frame_rate"}) {
    if (!archive.contains(key)) continue;
    const NpyArray rate = archive.array(key);
    if (rate.values.size() != 1) {
      throw core::InputError(fmt::format("{}[{}.npy]", where, key), "a single number", fmt::format("{} values", rate.values.size()));
    }
    fps = rate.values[0];
    break;
  }
  const size_t cols = poses.shape[1];
  std::vector<JointTargets> file_frames(frames);
  for (size_t f = 0; f < frames; ++f) {
    std::array<Vec3, kNumJoints> aa;
    for (size_t j = 0; j < aa.size(); ++j) {
      aa[j] = Vec3(poses.values[f * cols + 3 * j], poses.values[f * cols + 3 * j + 1], poses.values[f * cols + 3 * j + 2]);
    }
    file_frames[f] = smpl_forward_kinematics(aa, Vec3(trans.values[3 * f], trans.values[3 * f + 1], trans.values[3 * f + 2]));
  }
  UpAxis up = options.up;
  if (up == UpAxis::kAuto) {
    if (archive.contains("Rh")) {
      up = UpAxis::kY;
    } else if (archive.contains("mocap_framerate") || archive.contains("mocap_frame_rate")) {
      up = UpAxis::kZ;
    } else {
      const Vec3 d = file_frames[0].joint[u(Joint::kHead)] - file_frames[0].joint[0];
      up = std::abs(d.y()) >= std::abs(d.z()) ? UpAxis::kY : UpAxis::kZ;
    }
  }
  const core::Mat3 to_ours = up == UpAxis::kY ? y_up_to_z_up() : core::Mat3::Identity();
  for (JointTargets& t : file_frames) {
    for (Vec3& p : t.joint) p = to_ours * p;
    for (auto& tip : t.hand_tip) tip = to_ours * *tip;
  }
  RetargetOptions o = options;
  if (!o.ground) o.ground = true;
  return clip_from_targets(file_frames, fps, o, where);
}

Clip read_smplh(const std::filesystem::path& path, const RetargetOptions& options) {
  return clip_from_smplh(NpzArchive::Read(path), options, path.string());
}

std::string format_smplh(const Clip& clip) {
  const RestTree smpl = smpl_rest_tree();
  const double ratio = leg_length(JointTargets{[&] {
                         std::array<Vec3, kNumJoints> p{};
                         // SMPL rest positions, for its leg length.
                         for (int j = 1; j < kNumJoints; ++j) {
                           p[static_cast<size_t>(j)] = p[u(*parent(static_cast<Joint>(j)))] + smpl.offset[static_cast<size_t>(j)];
                         }
                         return p;
                       }(), {}}) / leg_length(clip.skeleton);
  const size_t F = clip.frames.size();
  std::vector<double> poses(F * 156, 0.0);
  std::vector<double> trans(F * 3, 0.0);
  for (size_t f = 0; f < F; ++f) {
    const auto X = forward_kinematics(clip.skeleton, clip.frames[f]);
    JointTargets t;  // our world = the archive's z-up world
    for (size_t j = 0; j < X.size(); ++j) t.joint[j] = X[j].translation;
    t.hand_tip[0] = X[u(Joint::kLeftWrist)] * Vec3(0, 0, -clip.skeleton.hand_length);
    t.hand_tip[1] = X[u(Joint::kRightWrist)] * Vec3(0, 0, -clip.skeleton.hand_length);
    const auto R = solve_world_rotations(smpl, t);
    for (int j = 0; j < kNumJoints; ++j) {
      const auto uj = static_cast<size_t>(j);
      const Quat local = j == 0 ? R[0] : Quat(R[u(*parent(static_cast<Joint>(j)))].conjugate() * R[uj]);
      const Vec3 aa = to_axis_angle(local);
      for (size_t k = 0; k < 3; ++k) poses[f * 156 + 3 * uj + k] = aa[static_cast<Eigen::Index>(k)];
    }
    const Vec3 tr = X[0].translation * ratio - smpl_pelvis_rest();
    for (size_t k = 0; k < 3; ++k) trans[f * 3 + k] = tr[static_cast<Eigen::Index>(k)];
  }
  std::map<std::string, std::string> members;
  members["poses"] = format_npy({F, 156}, poses, NpyType::kFloat64);
  members["trans"] = format_npy({F, 3}, trans, NpyType::kFloat64);
  members["betas"] = format_npy({16}, std::vector<double>(16, 0.0), NpyType::kFloat64);
  members["mocap_framerate"] = format_npy({}, {clip.fps}, NpyType::kFloat64);
  return format_npz(members);
}

}  // namespace hribench::human
