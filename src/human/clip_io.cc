#include "human/clip_io.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/json.h"
#include "human/bvh.h"
#include "human/npy.h"
#include "human/smplh.h"

namespace hribench::human {
namespace {

using Json = nlohmann::json;
using core::Vec3;

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::InputError::Message(path.string(), "cannot open the motion file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void write_bytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw core::InputError::Message(path.string(), "cannot write the file (missing directory or no permission?)");
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw core::InputError::Message(path.string(), "writing the file failed");
}

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// Typed JSON access; `path` is the key path for errors.
class Reader {
 public:
  explicit Reader(std::string_view where) : where_(where) {}
  [[noreturn]] void fail(const std::string& path, std::string expected, const Json& got) const {
    throw core::InputError(fmt::format("{}: {}", where_, path), std::move(expected),
                           got.is_null() ? "nothing" : got.dump().substr(0, 40));
  }
  const Json& member(const Json& object, const std::string& key, const std::string& path) const {
    if (!object.is_object()) fail(path, "an object", object);
    const auto it = object.find(key);
    if (it == object.end()) fail(path + "." + key, fmt::format("a member '{}'", key), Json());
    return *it;
  }
  double number(const Json& v, const std::string& path) const {
    if (!v.is_number()) fail(path, "a number", v);
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(path, "a finite number", v);
    return d;
  }
  const Json& array(const Json& v, const std::string& path, size_t size) const {
    if (!v.is_array() || (size != 0 && v.size() != size)) {
      fail(path, size ? fmt::format("an array of {} entries", size) : "an array", v);
    }
    return v;
  }
  core::Quat quat(const Json& v, const std::string& path) const {
    array(v, path, 4);
    const double wxyz[4] = {number(v[0], path + "[0]"), number(v[1], path + "[1]"), number(v[2], path + "[2]"),
                            number(v[3], path + "[3]")};
    const core::Quat q = core::quat_from_wxyz(wxyz);
    if (std::abs(q.norm() - 1) > 1e-3) fail(path, "a unit quaternion [w, x, y, z]", v);
    return q.normalized();
  }

 private:
  std::string_view where_;
};

Json quat_json(const core::Quat& q) { return Json::array({q.w(), q.x(), q.y(), q.z()}); }

}  // namespace

std::string format_clip_json(const Clip& clip) {
  Json j;
  j["format"] = "hribench.clip";
  j["version"] = 1;
  j["skeleton"] = {{"height", clip.skeleton.height}};
  j["fps"] = clip.fps;
  j["active_hand"] = clip.active_hand ? Json(std::string(to_string(*clip.active_hand))) : Json();
  Json phases = Json::array();
  for (const Phase& p : clip.phases) phases.push_back({{"name", p.name}, {"start", p.start}, {"end", p.end}});
  j["phases"] = phases;
  Json names = Json::array();
  for (int k = 0; k < kNumJoints; ++k) names.push_back(std::string(joint_name(static_cast<Joint>(k))));
  j["joints"] = names;
  Json frames = Json::array();
  for (const SkeletonPose& pose : clip.frames) {
    const Vec3& p = pose.X_WP.translation;
    Json local = Json::array();
    for (size_t k = 0; k < pose.local.size(); ++k) local.push_back(quat_json(k == 0 ? core::Quat::Identity() : pose.local[k]));
    Json hands = Json::array();
    for (const HandShape& h : pose.hands) hands.push_back({{"grip", h.grip}, {"point", h.point}});
    frames.push_back({{"root", {{"p", {p.x(), p.y(), p.z()}}, {"q", quat_json(pose.X_WP.rotation)}}},
                      {"local", local},
                      {"hands", hands}});
  }
  j["frames"] = frames;
  return j.dump() + "\n";
}

Clip parse_clip_json(std::string_view text, std::string_view where) {
  const Json j = core::parse_json(text, where);  // nesting and number range bounded there
  const Reader r(where);
  const Json& format = r.member(j, "format", "");
  if (format != "hribench.clip") r.fail("format", "\"hribench.clip\"", format);
  const Json& version = r.member(j, "version", "");
  if (version != 1) r.fail("version", "1", version);
  Clip clip;
  const double height = r.number(r.member(r.member(j, "skeleton", ""), "height", "skeleton"), "skeleton.height");
  if (height < 1.0 || height > 2.5) r.fail("skeleton.height", "a height in [1.0, 2.5] m", Json(height));
  clip.skeleton = Skeleton::FromHeight(height);
  clip.fps = r.number(r.member(j, "fps", ""), "fps");
  if (clip.fps <= 0 || clip.fps > 1000) r.fail("fps", "a frame rate in (0, 1000]", Json(clip.fps));
  if (j.contains("active_hand") && !j["active_hand"].is_null()) {
    const Json& hand = j["active_hand"];
    if (hand == "left") clip.active_hand = Side::kLeft;
    else if (hand == "right") clip.active_hand = Side::kRight;
    else r.fail("active_hand", "\"left\", \"right\" or null", hand);
  }
  if (j.contains("phases")) {
    const Json& phases = r.array(j["phases"], "phases", 0);
    for (size_t i = 0; i < phases.size(); ++i) {
      const std::string path = fmt::format("phases[{}]", i);
      const Json& name = r.member(phases[i], "name", path);
      if (!name.is_string()) r.fail(path + ".name", "a string", name);
      Phase p{name.get<std::string>(), r.number(r.member(phases[i], "start", path), path + ".start"),
              r.number(r.member(phases[i], "end", path), path + ".end")};
      if (p.end < p.start) r.fail(path, "start <= end", phases[i]);
      clip.phases.push_back(std::move(p));
    }
  }
  const Json& names = r.array(r.member(j, "joints", ""), "joints", kNumJoints);
  for (int k = 0; k < kNumJoints; ++k) {
    if (names[static_cast<size_t>(k)] != joint_name(static_cast<Joint>(k))) {
      r.fail(fmt::format("joints[{}]", k), fmt::format("\"{}\"", joint_name(static_cast<Joint>(k))), names[static_cast<size_t>(k)]);
    }
  }
  const Json& frames = r.array(r.member(j, "frames", ""), "frames", 0);
  if (frames.empty()) r.fail("frames", "at least one frame", frames);
  for (size_t f = 0; f < frames.size(); ++f) {
    const std::string path = fmt::format("frames[{}]", f);
    SkeletonPose pose;
    const Json& root = r.member(frames[f], "root", path);
    const Json& p = r.array(r.member(root, "p", path + ".root"), path + ".root.p", 3);
    pose.X_WP.translation = Vec3(r.number(p[0], path + ".root.p[0]"), r.number(p[1], path + ".root.p[1]"),
                                 r.number(p[2], path + ".root.p[2]"));
    pose.X_WP.rotation = r.quat(r.member(root, "q", path + ".root"), path + ".root.q");
    const Json& local = r.array(r.member(frames[f], "local", path), path + ".local", kNumJoints);
    for (size_t k = 1; k < local.size(); ++k) pose.local[k] = r.quat(local[k], fmt::format("{}.local[{}]", path, k));
    // Hand shapes are optional (a clip converted from motion capture has none: open hands).
    if (frames[f].contains("hands")) {
      const Json& hands = r.array(frames[f]["hands"], path + ".hands", 2);
      for (size_t h = 0; h < 2; ++h) {
        const std::string at = fmt::format("{}.hands[{}]", path, h);
        for (const auto& [key, value] : {std::pair{"grip", &pose.hands[h].grip}, std::pair{"point", &pose.hands[h].point}}) {
          *value = r.number(r.member(hands[h], key, at), at + "." + key);
          if (*value < 0 || *value > 1) r.fail(at + "." + key, "a number in [0, 1]", Json(*value));
        }
      }
    }
    clip.frames.push_back(pose);
  }
  return clip;
}

std::string format_humanml3d(const Clip& clip) {
  const core::Mat3 to_file = y_up_to_z_up().transpose();
  std::vector<double> values;
  values.reserve(clip.frames.size() * kNumJoints * 3);
  for (const SkeletonPose& pose : clip.frames) {
    for (const core::Pose& X : forward_kinematics(clip.skeleton, pose)) {
      const Vec3 p = to_file * X.translation;
      values.insert(values.end(), {p.x(), p.y(), p.z()});
    }
  }
  return format_npy({clip.frames.size(), static_cast<size_t>(kNumJoints), 3}, values, NpyType::kFloat32);
}

Clip parse_humanml3d(std::string_view npy_bytes, double fps, const RetargetOptions& options,
                     std::string_view where) {
  const NpyArray a = parse_npy(npy_bytes, where);
  if (a.shape.size() != 3 || a.shape[1] != static_cast<size_t>(kNumJoints) || a.shape[2] != 3 || a.shape[0] == 0) {
    std::string shape;
    for (const size_t d : a.shape) shape += fmt::format("{}{}", shape.empty() ? "" : ", ", d);
    throw core::InputError(fmt::format("{}: byte 0 (header)", where), "shape (frames, 22, 3)",
                           fmt::format("({})", shape));
  }
  for (size_t i = 0; i < a.values.size(); ++i) {
    if (!std::isfinite(a.values[i])) {
      throw core::InputError(fmt::format("{}: byte {}", where, a.data_offset + i * a.item_size),
                             "finite joint positions",
                             fmt::format("{} (frame {}, joint {}, axis {})", a.values[i], i / 66, (i / 3) % 22, i % 3));
    }
  }
  const core::Mat3 to_ours = options.up == UpAxis::kZ ? core::Mat3::Identity() : y_up_to_z_up();
  std::vector<JointTargets> frames(a.shape[0]);
  for (size_t f = 0; f < frames.size(); ++f) {
    for (size_t j = 0; j < static_cast<size_t>(kNumJoints); ++j) {
      const size_t i = (f * kNumJoints + j) * 3;
      frames[f].joint[j] = to_ours * Vec3(a.values[i], a.values[i + 1], a.values[i + 2]);
    }
  }
  return clip_from_targets(frames, fps, options, where);
}

Clip read_clip(const std::filesystem::path& path, const RetargetOptions& options) {
  const std::string ext = lower_extension(path);
  const std::string where = path.string();
  if (ext == ".bvh") return clip_from_bvh(read_bvh(path), options, where);
  if (ext == ".npz") return read_smplh(path, options);
  if (ext == ".json") return parse_clip_json(read_bytes(path), where);
  if (ext == ".npy") {
    double fps = 20;  // HumanML3D
    std::filesystem::path sidecar = path;
    sidecar += ".json";
    if (std::filesystem::exists(sidecar)) {
      const Json meta = core::parse_json(read_bytes(sidecar), sidecar.string());
      if (!meta.is_object() || !meta.contains("fps") || !meta["fps"].is_number()) {
        throw core::InputError(sidecar.string() + ": fps", "a number", meta.dump().substr(0, 40));
      }
      fps = meta["fps"].get<double>();
    }
    return parse_humanml3d(read_bytes(path), fps, options, where);
  }
  throw core::InputError(where, "a motion file ending in .bvh, .npy, .npz or .json", fmt::format("'{}'", ext));
}

void write_clip(const Clip& clip, const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".json") {
    write_bytes(path, format_clip_json(clip));
  } else if (ext == ".bvh") {
    write_bytes(path, format_bvh(bvh_from_clip(clip, BvhRotationOrder::kZYX)));
  } else if (ext == ".npy") {
    write_bytes(path, format_humanml3d(clip));
    std::filesystem::path sidecar = path;
    sidecar += ".json";
    write_bytes(sidecar, Json({{"fps", clip.fps}, {"layout", "humanml3d new_joints (frames, 22, 3), y-up, m"}}).dump() + "\n");
  } else if (ext == ".npz") {
    write_bytes(path, format_smplh(clip));
  } else {
    throw core::InputError(path.string(), "an output file ending in .json, .bvh, .npy or .npz", fmt::format("'{}'", ext));
  }
}

}  // namespace hribench::human
