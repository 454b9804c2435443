#include "remote/preset.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/errors.h"
#include "core/json.h"
#include "script/schema_io.h"

namespace hribench::remote {
namespace {

using policy::ActionChunk;
using policy::ActionSpace;
using policy::PolicyError;
using policy::PolicyErrorKind;

constexpr int kWholeChunk = std::numeric_limits<int>::max();  // replan_every: execute every action

[[noreturn]] void bad_reply(const std::string& message) { throw PolicyError(PolicyErrorKind::kWrongShape, message); }

NdArray vector_array(const std::vector<double>& values, std::string_view dtype) {
  return NdArray::from_doubles(values, {values.size()}, dtype);
}

// A (H, D) or (H,) group as H rows of D values (D = 1 for (H,)).
std::vector<std::vector<double>> rows(const NdArray& a, const std::string& name) {
  if (a.shape.empty() || a.shape.size() > 2) {
    bad_reply(fmt::format("action '{}': expected shape (H, D) or (H,), got {} dimensions", name, a.shape.size()));
  }
  const std::vector<double> values = a.to_doubles("action '" + name + "'");
  const size_t h = a.shape[0];
  const size_t d = a.shape.size() == 2 ? a.shape[1] : 1;
  std::vector<std::vector<double>> out(h);
  for (size_t i = 0; i < h; ++i) out[i].assign(values.begin() + static_cast<long>(i * d), values.begin() + static_cast<long>((i + 1) * d));
  return out;
}

// Concatenates the groups of `layout` row by row, or takes the single array "actions".
std::vector<std::vector<double>> concatenated(const ActionGroups& groups,
                                              const std::vector<std::pair<std::string, int>>& layout) {
  int width = 0;
  for (const auto& [name, w] : layout) width += w;
  std::string present;
  for (const auto& [name, array] : groups) present += (present.empty() ? "" : ", ") + name;
  const auto group = [&](const std::string& name) -> const NdArray* {
    for (const auto& [n, array] : groups) {
      if (n == name) return &array;
    }
    return nullptr;
  };
  if (const NdArray* actions = group("actions")) {
    std::vector<std::vector<double>> out = rows(*actions, "actions");
    if (actions->shape.size() != 2 || static_cast<int>(actions->shape[1]) < width) {
      bad_reply(fmt::format("actions: expected shape (H, {}), got ({})", width, fmt::join(actions->shape, ", ")));
    }
    for (auto& row : out) row.resize(static_cast<size_t>(width));  // openpi pads; keep the first D
    return out;
  }
  std::vector<std::vector<double>> out;
  for (const auto& [name, w] : layout) {
    const NdArray* a = group(name);
    if (a == nullptr) {
      std::vector<std::string> names;  // not views::keys: the fuzz build's clang-14 cannot compile it over libstdc++ 12
      for (const auto& entry : layout) names.push_back(entry.first);
      bad_reply(fmt::format("no 'actions' in the reply (got: {}; or the groups {})", present.empty() ? "none" : present,
                            fmt::join(names, ", ")));
    }
    const std::vector<std::vector<double>> part = rows(*a, name);
    if (out.empty()) out.resize(part.size());
    if (part.size() != out.size()) {
      bad_reply(fmt::format("action '{}': {} steps, the other groups have {}", name, part.size(), out.size()));
    }
    for (size_t i = 0; i < part.size(); ++i) {
      if (static_cast<int>(part[i].size()) != w) {
        bad_reply(fmt::format("action '{}': expected {} values per step, got {}", name, w, part[i].size()));
      }
      out[i].insert(out[i].end(), part[i].begin(), part[i].end());
    }
  }
  return out;
}

std::vector<double> pose_values(const core::Pose& X) {
  const core::Vec3& p = X.translation;
  const core::Quat& q = X.rotation;
  return {p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z()};
}

core::Pose pose_from(const double* v) {
  core::Pose X;
  X.translation = core::Vec3(v[0], v[1], v[2]);
  X.rotation = core::Quat(v[3], v[4], v[5], v[6]);
  return X;
}

// ---- hribench ----------------------------------------------------------------------------

class NativePreset : public Preset {
 public:
  NativePreset(policy::PolicySpec spec, std::string dtype) : spec_(std::move(spec)), dtype_(std::move(dtype)) {}
  std::string name() const override { return "hribench"; }
  policy::PolicySpec spec() const override { return spec_; }
  void begin(const policy::EpisodeInfo& info) override {
    info_ = info;
    first_ = true;
  }

  ObservationGroups encode(const policy::Observation& obs) override {
    ObservationGroups g;
    for (const policy::Image& image : obs.images) {
      g.video.emplace_back(image.camera,
                           NdArray::from_bytes(image.pixels.data(), {static_cast<size_t>(image.height),
                                                                     static_cast<size_t>(image.width), 3}));
    }
    const policy::Proprioception& p = obs.proprio;
    g.state.emplace_back("joint_position", vector_array({p.joint_pos.begin(), p.joint_pos.end()}, dtype_));
    g.state.emplace_back("joint_velocity", vector_array({p.joint_vel.begin(), p.joint_vel.end()}, dtype_));
    g.state.emplace_back("gripper_width", vector_array({p.gripper_width}, dtype_));
    g.state.emplace_back("tcp_pose", vector_array(pose_values(p.X_WT), dtype_));
    g.state.emplace_back("time", vector_array({obs.time}, dtype_));
    if (obs.state) {
      std::vector<double> joints;
      for (const core::Vec3& j : obs.state->human_joints_W) joints.insert(joints.end(), {j.x(), j.y(), j.z()});
      g.state.emplace_back("human_joints", vector_array(joints, dtype_));
      std::vector<double> poses;
      List names;
      for (const policy::ObjectPose& o : obs.state->objects) {
        const std::vector<double> v = pose_values(o.X_WO);
        poses.insert(poses.end(), v.begin(), v.end());
        names.emplace_back(o.name);
      }
      g.state.emplace_back("object_poses", vector_array(poses, dtype_));
      g.extras.emplace_back("object_names", std::move(names));
    }
    g.language = obs.instruction;
    if (first_) {
      Map start{{"task", info_.task},
                {"instruction", info_.instruction},
                {"seed", std::to_string(info_.seed)},
                {"horizon", info_.horizon},
                {"control_dt", info_.control_dt},
                {"robot", info_.robot}};
      if (spec_.privileged && info_.episode) {
        start.emplace_back("episode", core::canonical_json(script::to_json(*info_.episode)));
      }
      g.extras.emplace_back("reset", std::move(start));
      first_ = false;
    }
    if (spec_.privileged) {
      List events;
      for (const policy::ScriptEvent& e : obs.events) events.emplace_back(List{e.time, e.kind, e.name, e.detail});
      g.extras.emplace_back("events", std::move(events));
    }
    return g;
  }

  ActionChunk decode(const ActionGroups& groups) override {
    ActionChunk chunk;
    chunk.space = spec_.action_space;
    chunk.actions = concatenated(groups, action_layout());
    return chunk;
  }

  std::vector<std::pair<std::string, int>> action_layout() const override {
    if (spec_.action_space == ActionSpace::kEeDelta) return {{"eef_delta", 6}, {"gripper", 1}};
    const model::Robot& robot = model::robot_by_name(info_.robot);
    return {{"joint_position", static_cast<int>(robot.dof())}, {"gripper", 1}};
  }

 private:
  policy::PolicySpec spec_;
  std::string dtype_;
  policy::EpisodeInfo info_;
  bool first_ = true;
};

// ---- libero (openpi pi05_libero) -----------------------------------------------------------

// robosuite's OSC_POSE controller as LIBERO configures it: inputs clipped to [-1, 1], scaled to
// at most 0.05 m and 0.5 rad per control step (20 Hz, as ours).
constexpr double kLiberoMaxTranslation = 0.05;  // m per step
constexpr double kLiberoMaxRotation = 0.5;      // rad per step
constexpr int kLiberoReplan = 5;                // examples/libero/main.py replan_steps

// An upright image mirrored left-right: robosuite renders bottom-up (OpenGL) and LIBERO's
// example rotates that by 180 degrees, which is the upright image mirrored.
NdArray mirrored(const policy::Image& image) {
  NdArray a;
  a.dtype = "|u1";
  a.shape = {static_cast<size_t>(image.height), static_cast<size_t>(image.width), 3};
  a.data.resize(image.pixels.size());
  const size_t w = static_cast<size_t>(image.width);
  for (size_t r = 0; r < static_cast<size_t>(image.height); ++r) {
    for (size_t c = 0; c < w; ++c) {
      std::memcpy(a.data.data() + (r * w + c) * 3, image.pixels.data() + (r * w + (w - 1 - c)) * 3, 3);
    }
  }
  return a;
}

// robosuite's quat2axisangle (LIBERO's example): angle 2 acos(w) in [0, 2 pi] about the axis.
core::Vec3 quat_to_axis_angle(const core::Quat& q) {
  const double w = std::clamp(q.w(), -1.0, 1.0);
  const double den = std::sqrt(1.0 - w * w);
  if (den < 1e-12) return core::Vec3::Zero();
  return core::Vec3(q.x(), q.y(), q.z()) * (2.0 * std::acos(w)) / den;
}

const policy::Image& image_of(const policy::Observation& obs, const std::string& camera) {
  for (const policy::Image& image : obs.images) {
    if (image.camera == camera) return image;
  }
  HRIB_CHECK(false) << "no image of camera " << camera;
  return obs.images.front();
}

class LiberoPreset : public Preset {
 public:
  std::string name() const override { return "libero"; }
  policy::PolicySpec spec() const override {
    policy::PolicySpec spec;
    spec.cameras = {{"agentview", 224, 224}, {"wrist", 224, 224}};
    spec.action_space = ActionSpace::kEeDelta;
    spec.replan_every = kLiberoReplan;
    return spec;
  }
  void begin(const policy::EpisodeInfo&) override {}
  ObservationGroups encode(const policy::Observation& obs) override {
    ObservationGroups g;
    g.video.emplace_back("image", mirrored(image_of(obs, "agentview")));
    g.video.emplace_back("wrist_image", mirrored(image_of(obs, "wrist")));
    const core::Vec3& p = obs.proprio.X_WT.translation;
    const core::Vec3 r = quat_to_axis_angle(obs.proprio.X_WT.rotation);
    const double half = obs.proprio.gripper_width / 2;
    g.state.emplace_back("state", vector_array({p.x(), p.y(), p.z(), r.x(), r.y(), r.z(), half, -half}, "<f4"));
    g.language = obs.instruction;
    return g;
  }
  ActionChunk decode(const ActionGroups& groups) override {
    ActionChunk chunk;
    chunk.space = ActionSpace::kEeDelta;
    for (std::vector<double> a : concatenated(groups, action_layout())) {
      for (double& v : a) v = std::clamp(v, -1.0, 1.0);  // robosuite clips its input (NaN stays NaN)
      policy::Action action(7);
      for (int i = 0; i < 3; ++i) action[static_cast<size_t>(i)] = a[static_cast<size_t>(i)] * kLiberoMaxTranslation;
      for (int i = 3; i < 6; ++i) action[static_cast<size_t>(i)] = a[static_cast<size_t>(i)] * kLiberoMaxRotation;
      action[6] = (1.0 - a[6]) / 2.0;  // LIBERO: -1 open, +1 closed
      chunk.actions.push_back(std::move(action));
    }
    return chunk;
  }
  std::vector<std::pair<std::string, int>> action_layout() const override { return {{"actions", 7}}; }
};

// ---- droid (openpi pi05_droid) -------------------------------------------------------------

// DROID's RobotIKSolver: a normalised joint velocity v (scaled down so max |v| <= 1) moves each
// joint by v * 0.2 rad per control tick at 15 Hz; our step is control_dt long.
constexpr double kDroidMaxJointDelta = 0.2;  // rad per DROID tick
constexpr double kDroidHz = 15;
constexpr int kDroidReplan = 8;  // examples/droid/main.py open_loop_horizon
constexpr size_t kDroidDof = 7;

class DroidPreset : public Preset {
 public:
  std::string name() const override { return "droid"; }
  policy::PolicySpec spec() const override {
    policy::PolicySpec spec;
    spec.cameras = {{"agentview", 224, 224}, {"wrist", 224, 224}};
    spec.action_space = ActionSpace::kJointPos;
    spec.replan_every = kDroidReplan;
    return spec;
  }
  void begin(const policy::EpisodeInfo& info) override {
    const model::Robot& robot = model::robot_by_name(info.robot);
    if (robot.dof() != kDroidDof) {
      throw PolicyError(PolicyErrorKind::kFailed, fmt::format("preset droid needs a 7-joint arm, {} has {}", robot.name, robot.dof()));
    }
    max_width_ = robot.gripper.max_width();
    control_dt_ = info.control_dt;
  }
  ObservationGroups encode(const policy::Observation& obs) override {
    ObservationGroups g;
    g.video.emplace_back("exterior_image_1_left", image_array(image_of(obs, "agentview")));
    g.video.emplace_back("wrist_image_left", image_array(image_of(obs, "wrist")));
    const model::JointVector& q = obs.proprio.joint_pos;
    q_ = std::vector<double>(q.begin(), q.end());
    g.state.emplace_back("joint_position", vector_array(q_, "<f4"));
    g.state.emplace_back("gripper_position", vector_array({1.0 - obs.proprio.gripper_width / max_width_}, "<f4"));
    g.language = obs.instruction;
    return g;
  }
  ActionChunk decode(const ActionGroups& groups) override {
    ActionChunk chunk;
    chunk.space = ActionSpace::kJointPos;
    std::vector<double> q = q_;  // integrated from the observed joint positions
    const double scale = kDroidMaxJointDelta * kDroidHz * control_dt_;
    for (std::vector<double> a : concatenated(groups, action_layout())) {
      double norm = 0;
      for (size_t j = 0; j < kDroidDof; ++j) norm = std::max(norm, std::abs(a[j]));
      const double shrink = norm > 1 ? norm : 1;
      policy::Action action(kDroidDof + 1);
      for (size_t j = 0; j < kDroidDof; ++j) {
        q[j] += a[j] / shrink * scale;
        action[j] = q[j];
      }
      action[kDroidDof] = a[kDroidDof] > 0.5 ? 0.0 : 1.0;  // DROID: 1 closed (binarised at 0.5 as its example)
      chunk.actions.push_back(std::move(action));
    }
    return chunk;
  }
  std::vector<std::pair<std::string, int>> action_layout() const override { return {{"actions", 8}}; }

 private:
  static NdArray image_array(const policy::Image& image) {
    return NdArray::from_bytes(image.pixels.data(), {static_cast<size_t>(image.height), static_cast<size_t>(image.width), 3});
  }
  double max_width_ = 0.08;
  double control_dt_ = 0.05;
  std::vector<double> q_;
};

const NdArray& state_group(const ObservationGroups& g, const std::string& name) {
  for (const auto& [n, a] : g.state) {
    if (n == name) return a;
  }
  throw WireError(fmt::format("hribench layout: no state '{}'", name));
}

std::vector<double> state_values(const ObservationGroups& g, const std::string& name, size_t size) {
  std::vector<double> v = state_group(g, name).to_doubles("state '" + name + "'");
  if (size != 0 && v.size() != size) {
    throw WireError(fmt::format("state '{}': expected {} values, got {}", name, size, v.size()));
  }
  return v;
}

}  // namespace

Value spec_to_value(const policy::PolicySpec& spec) {
  List cameras;
  for (const policy::CameraRequest& c : spec.cameras) cameras.emplace_back(List{c.name, c.width, c.height});
  return Map{{"cameras", std::move(cameras)},
             {"state_track", spec.state_track},
             {"action_space", std::string(policy::to_string(spec.action_space))},
             {"replan_every", spec.replan_every},
             {"privileged", spec.privileged}};
}

policy::PolicySpec spec_from_value(const Value& value, std::string_view where) {
  const std::string w(where);
  const Map& m = value.map(w);
  policy::PolicySpec spec;
  for (const Value& c : at(m, "cameras", w).list(w + ".cameras")) {
    const List& camera = c.list(w + ".cameras[]");
    if (camera.size() != 3) throw WireError(w + ".cameras[]: expected [name, width, height]");
    spec.cameras.push_back({camera[0].str(w + ".cameras[].name"),
                            static_cast<int>(camera[1].number(w + ".cameras[].width")),
                            static_cast<int>(camera[2].number(w + ".cameras[].height"))});
  }
  const auto flag = [&](const char* key) {
    const Value& v = at(m, key, w);
    if (const auto* b = std::get_if<bool>(&v.v)) return *b;
    throw WireError(fmt::format("{}.{}: expected bool, got {}", w, key, v.kind()));
  };
  spec.state_track = flag("state_track");
  spec.privileged = flag("privileged");
  try {
    spec.action_space = policy::action_space_from_string(at(m, "action_space", w).str(w + ".action_space"), w);
  } catch (const core::InputError& e) {
    throw WireError(e.what());
  }
  spec.replan_every = std::max(1, static_cast<int>(at(m, "replan_every", w).number(w + ".replan_every")));
  return spec;
}

std::vector<std::string> preset_names() { return {"droid", "hribench", "libero"}; }

std::unique_ptr<Preset> make_preset(const PresetOptions& options, const std::string& where) {
  if (options.name == "hribench") {
    policy::PolicySpec spec;
    if (options.served_spec) {
      spec = *options.served_spec;
      if (spec.privileged && !options.allow_privileged) {
        throw core::InputError(where, "a server for a learner (no privileged track), or privileged=1 in the reference",
                               "a server asking for the privileged track (the episode and its events)");
      }
    } else {
      spec.cameras = {{"agentview", 224, 224}, {"wrist", 224, 224}};
      spec.action_space = options.space;
      spec.replan_every = kWholeChunk;
    }
    if (options.state_dtype != "<f8" && options.state_dtype != "<f4") {
      throw core::InputError(where + ": dtype", "f8 or f4", "'" + options.state_dtype + "'");
    }
    return std::make_unique<NativePreset>(spec, options.state_dtype);
  }
  if (options.name == "libero") return std::make_unique<LiberoPreset>();
  if (options.name == "droid") return std::make_unique<DroidPreset>();
  std::string names;
  for (const std::string& n : preset_names()) names += (names.empty() ? "" : ", ") + n;
  throw core::InputError(where, "a preset (" + names + ")", "'" + options.name + "'");
}

NativeQuery decode_native(const ObservationGroups& g, const policy::PolicySpec& spec) {
  NativeQuery q;
  if (const Value* start = find(g.extras, "reset")) {
    const Map& m = start->map("hribench/reset");
    policy::EpisodeInfo info;
    info.task = at(m, "task", "reset").str("reset.task");
    info.instruction = at(m, "instruction", "reset").str("reset.instruction");
    info.seed = std::stoull(at(m, "seed", "reset").str("reset.seed"));
    info.horizon = at(m, "horizon", "reset").number("reset.horizon");
    info.control_dt = at(m, "control_dt", "reset").number("reset.control_dt");
    info.robot = at(m, "robot", "reset").str("reset.robot");
    if (const Value* episode = find(m, "episode")) {
      const core::Json json = core::parse_json(episode->str("reset.episode"), "hribench/reset.episode");
      info.episode = std::make_shared<const script::EpisodeSpec>(script::episode_from_json(json, "hribench/reset.episode"));
    }
    q.start = std::move(info);
  }
  policy::Observation& obs = q.observation;
  for (const policy::CameraRequest& c : spec.cameras) {
    const NdArray* found = nullptr;
    for (const auto& [name, a] : g.video) {
      if (name == c.name) found = &a;
    }
    if (found == nullptr) throw WireError(fmt::format("hribench layout: no image '{}'", c.name));
    if (found->dtype != "|u1" || found->shape != std::vector<size_t>{static_cast<size_t>(c.height), static_cast<size_t>(c.width), 3}) {
      throw WireError(fmt::format("image '{}': expected uint8 ({}, {}, 3)", c.name, c.height, c.width));
    }
    policy::Image image;
    image.camera = c.name;
    image.width = c.width;
    image.height = c.height;
    image.pixels.assign(found->data.begin(), found->data.end());
    obs.images.push_back(std::move(image));
  }
  const std::vector<double> q_pos = state_values(g, "joint_position", 0);
  const std::vector<double> q_vel = state_values(g, "joint_velocity", q_pos.size());
  if (q_pos.size() > model::kMaxArmDof) throw WireError("state 'joint_position': too many joints");
  obs.proprio.joint_pos = model::JointVector(q_pos.size());
  obs.proprio.joint_vel = model::JointVector(q_pos.size());
  std::copy(q_pos.begin(), q_pos.end(), obs.proprio.joint_pos.begin());
  std::copy(q_vel.begin(), q_vel.end(), obs.proprio.joint_vel.begin());
  obs.proprio.gripper_width = state_values(g, "gripper_width", 1)[0];
  obs.proprio.X_WT = pose_from(state_values(g, "tcp_pose", 7).data());
  obs.time = state_values(g, "time", 1)[0];
  obs.instruction = g.language;
  if (spec.state_track) {
    policy::StateObservation state;
    const std::vector<double> joints = state_values(g, "human_joints", 3 * policy::kHumanKeypoints);
    for (size_t i = 0; i < state.human_joints_W.size(); ++i) {
      state.human_joints_W[i] = core::Vec3(joints[3 * i], joints[3 * i + 1], joints[3 * i + 2]);
    }
    const List& names = at(g.extras, "object_names", "hribench extras").list("object_names");
    const std::vector<double> poses = state_values(g, "object_poses", 7 * names.size());
    for (size_t i = 0; i < names.size(); ++i) {
      state.objects.push_back({names[i].str("object_names[]"), pose_from(poses.data() + 7 * i)});
    }
    obs.state = std::move(state);
  }
  if (spec.privileged) {
    for (const Value& e : at(g.extras, "events", "hribench extras").list("events")) {
      const List& fields = e.list("events[]");
      if (fields.size() != 4) throw WireError("events[]: expected [time, kind, name, detail]");
      obs.events.push_back({fields[0].number("events[].time"), fields[1].str("events[].kind"),
                            fields[2].str("events[].name"), fields[3].str("events[].detail")});
    }
  }
  return q;
}

ActionGroups encode_native_actions(const policy::ActionChunk& chunk, bool named) {
  const size_t width = chunk.actions.empty() ? 0 : chunk.actions[0].size();
  std::vector<double> values;
  for (const policy::Action& a : chunk.actions) {
    if (a.size() != width) throw PolicyError(PolicyErrorKind::kWrongShape, "the served policy's actions differ in size");
    values.insert(values.end(), a.begin(), a.end());
  }
  const size_t h = chunk.actions.size();
  if (!named) return {{"actions", NdArray::from_doubles(values, {h, width}, "<f8")}};
  // The groups: eef_delta (H, 6) or joint_position (H, dof), then gripper (H, 1).
  std::vector<double> arm;
  std::vector<double> gripper;
  for (const policy::Action& a : chunk.actions) {
    arm.insert(arm.end(), a.begin(), a.end() - 1);
    gripper.push_back(a.back());
  }
  return {{chunk.space == ActionSpace::kEeDelta ? "eef_delta" : "joint_position",
           NdArray::from_doubles(arm, {h, width - 1}, "<f8")},
          {"gripper", NdArray::from_doubles(gripper, {h, 1}, "<f8")}};
}

}  // namespace hribench::remote
