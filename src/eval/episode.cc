#include "eval/episode.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <tuple>
#include <utility>

#include <mujoco/mujoco.h>

#include "core/errors.h"
#include "eval/script_contract.h"
#include "eval/script_driver.h"
#include "script/sample.h"
#include "sim/contact.h"
#include "sim/control.h"

namespace hribench::eval {

EpisodeSetup setup_of(const script::EpisodeSpec& spec, std::string policy) {
  return {spec.task, spec.role, script::spec_hash(spec), spec.seed, spec.instruction, std::move(policy)};
}

namespace {

// Containers and placement fixtures count as environment for collisions (CFR); the things a
// robot manipulates count as objects.
bool is_fixture(model::ObjectKind kind) {
  return kind == model::ObjectKind::kBin || kind == model::ObjectKind::kBox ||
         kind == model::ObjectKind::kTray || kind == model::ObjectKind::kPlate;
}

// One (robot part, other party) pair among a step's contacts, keyed by ids so that names are
// made once per pair, not once per contact point.
struct ContactPair {
  std::array<int, 4> key{};             // robot owner, robot index, other owner, other id
  const sim::Contact* first = nullptr;  // the pair's first contact (names its parties)
  double normal_force = 0;              // N, summed over the pair's contacts
};

// Ids that name a party exactly as robot_contacts names it.
std::array<int, 4> pair_key(const sim::Contact& c) {
  int other = c.b.geom;  // environment geoms are named by geom
  switch (c.b.owner) {
    case model::GeomOwner::kHuman:
    case model::GeomOwner::kObject:
      other = c.b.index;
      break;
    case model::GeomOwner::kTable:
    case model::GeomOwner::kFloor:
    case model::GeomOwner::kPlatform:
      other = 0;
      break;
    default:
      break;
  }
  const int robot = c.a.owner == model::GeomOwner::kRobotHand ? 0 : c.a.index;
  return {static_cast<int>(c.a.owner), robot, static_cast<int>(c.b.owner), other};
}

// The robot's contacts, one per (robot part, other) pair with the forces summed, ordered by
// (robot part, other) name. `pairs` is scratch, reused between steps.
std::vector<Contact> robot_contacts(const model::Model& model, const std::vector<sim::Contact>& all,
                                    std::vector<ContactPair>& pairs) {
  // Sum the forces per pair (a sorted vector: a step has few pairs).
  pairs.clear();
  for (const sim::Contact& c : all) {
    if (!c.a.is_robot() || c.b.is_robot()) continue;  // robot vs something else only
    const std::array<int, 4> key = pair_key(c);
    auto it = std::lower_bound(pairs.begin(), pairs.end(), key,
                               [](const ContactPair& p, const std::array<int, 4>& k) { return p.key < k; });
    if (it == pairs.end() || it->key != key) it = pairs.insert(it, ContactPair{key, &c, 0.0});
    it->normal_force += c.normal_force;
  }
  // Name each pair once.
  std::vector<Contact> contacts;
  contacts.reserve(pairs.size());
  for (const ContactPair& p : pairs) {
    const sim::Contact& c = *p.first;
    Contact out;
    out.robot_part = sim::party_name(model, c.a);
    out.robot_finger = c.a.owner == model::GeomOwner::kRobotFinger;
    switch (c.b.owner) {
      case model::GeomOwner::kHuman:
        out.other_kind = ContactOther::kHuman;
        out.other = std::string(model.human_capsules[static_cast<size_t>(c.b.index)].name);
        out.region = c.b.region;
        break;
      case model::GeomOwner::kObject: {
        const model::ObjectInfo& object = model.objects[static_cast<size_t>(c.b.index)];
        out.other_kind = is_fixture(object.kind) ? ContactOther::kEnvironment : ContactOther::kObject;
        out.other = object.name;
        break;
      }
      default:
        out.other_kind = ContactOther::kEnvironment;
        out.other = sim::party_name(model, c.b);
        break;
    }
    out.normal_force = p.normal_force;
    contacts.push_back(std::move(out));
  }
  // Name order; should two pairs share names, they are one contact.
  const auto by_name = [](const Contact& a, const Contact& b) {
    return std::tie(a.robot_part, a.other) < std::tie(b.robot_part, b.other);
  };
  std::sort(contacts.begin(), contacts.end(), by_name);
  size_t kept = 0;
  for (size_t i = 0; i < contacts.size(); ++i) {
    if (kept > 0 && contacts[kept - 1].robot_part == contacts[i].robot_part &&
        contacts[kept - 1].other == contacts[i].other) {
      contacts[kept - 1].normal_force += contacts[i].normal_force;
    } else {
      if (kept != i) contacts[kept] = std::move(contacts[i]);
      ++kept;
    }
  }
  contacts.resize(kept);
  return contacts;
}

core::Pose body_pose(const mjData& d, int body) {
  core::Pose pose;
  pose.translation = core::Vec3(d.xpos[3 * body], d.xpos[3 * body + 1], d.xpos[3 * body + 2]);
  pose.rotation = core::quat_from_wxyz(d.xquat + 4 * body);
  return pose;
}

}  // namespace

// Everything an episode rebuilds rather than copies: the renderers of the requested cameras
// (made for this episode's model; one per image size, shared by the cameras of that size) and
// the contact scratch.
struct Episode::Scratch {
  std::vector<std::unique_ptr<render::Renderer>> renderers;  // an episode without a scene
  std::vector<render::Renderer*> renderer_of;  // per requested camera (the scene's or ours)
  std::vector<int> camera_ids;
  std::vector<sim::Contact> contacts;
  std::vector<ContactPair> pairs;
};

namespace {

// The episode's model for a spec: the given one or its scene's.
std::shared_ptr<const model::Model> model_for(const script::EpisodeSpec& spec,
                                              std::shared_ptr<const model::Model> model) {
  if (model) return model;
  return std::make_shared<const model::Model>(model::build(scene_spec_from_episode(spec)));
}

// The renderer of `renderers` for width x height on `backend`, made for `m` when there is none.
render::Renderer& renderer_in(std::vector<std::unique_ptr<render::Renderer>>& renderers, render::Backend backend,
                              const mjModel& m, int width, int height) {
  const auto same = std::find_if(renderers.begin(), renderers.end(), [&](const auto& r) {
    return r->backend() == backend && r->width() == width && r->height() == height;
  });
  if (same != renderers.end()) return **same;
  renderers.push_back(render::make_renderer(backend, m, width, height));
  return *renderers.back();
}

}  // namespace

EpisodeScene::EpisodeScene(script::EpisodeSpec spec, std::shared_ptr<const model::Model> model)
    : spec_(std::make_shared<const script::EpisodeSpec>(std::move(spec))),
      model_(model_for(*spec_, std::move(model))),
      data_(sim::make_data(*model_)) {
  auto driver = std::make_unique<ScriptDriver>(spec_);
  // The contract, with the home TCP of the scene's fresh data (no second Data).
  contract_ = std::make_shared<const ScenarioContract>(
      contract_from_episode(*spec_, driver->graph(), *model_, sim::tcp_pose(*model_, data_).translation));
  driver_ = std::move(driver);
}

EpisodeScene::~EpisodeScene() = default;

render::Renderer& EpisodeScene::renderer(render::Backend backend, int width, int height) {
  return renderer_in(renderers_, backend, *model_->m(), width, height);
}

Episode::Episode(script::EpisodeSpec spec, const policy::PolicySpec& policy, EpisodeSetup setup,
                 RunOptions options, std::shared_ptr<const model::Model> model)
    : Episode(std::make_unique<EpisodeScene>(std::move(spec), std::move(model)), policy, std::move(setup),
              std::move(options)) {}

Episode::Episode(std::unique_ptr<EpisodeScene> scene, const policy::PolicySpec& policy, EpisodeSetup setup,
                 RunOptions options)
    : Episode(*scene, policy, std::move(setup), std::move(options)) {
  own_scene_ = std::move(scene);  // (should the episode throw, `scene` still owns it)
}

Episode::Episode(EpisodeScene& scene, const policy::PolicySpec& policy, EpisodeSetup setup, RunOptions options)
    : spec_(scene.spec_),
      own_model_(scene.model_),
      model_(own_model_.get()),
      contract_(scene.contract_),
      policy_(policy),
      setup_(std::move(setup)),
      options_(std::move(options)),
      scene_(&scene) {
  if (options_.horizon <= 0) options_.horizon = spec_->horizon;
  data_ = &scene.data_;
  own_driver_ = scene.driver_->clone();
  driver_ = own_driver_.get();
  init();
}

Episode::Episode(const model::Model& model, sim::Data& data, ScenarioDriver& driver,
                 const policy::PolicySpec& policy, EpisodeSetup setup, RunOptions options)
    : model_(&model),
      policy_(policy),
      setup_(std::move(setup)),
      options_(std::move(options)),
      data_(&data),
      driver_(&driver) {
  init();
}

Episode::Episode(const Episode& other)
    : spec_(other.spec_),
      own_model_(other.own_model_),
      model_(other.model_),
      contract_(other.contract_),
      policy_(other.policy_),
      setup_(other.setup_),
      options_(other.options_) {
  init();
  own_data_ = std::make_unique<sim::Data>(sim::make_data(*model_));
  data_ = own_data_.get();
  restore(other.snapshot());
}

Episode::~Episode() = default;

void Episode::init() {
  const double timestep = model_->m()->opt.timestep;
  const double physics_per_control = options_.control_dt / timestep;
  substeps_ = static_cast<int>(std::lround(physics_per_control));
  if (substeps_ < 1 || std::abs(physics_per_control - substeps_) > 1e-9) {
    throw core::InputError("control_dt", fmt::format("a whole number of {} ms physics steps", 1000 * timestep),
                           fmt::format("{} s", options_.control_dt));
  }
  if (!(options_.horizon > 0)) {
    throw core::InputError("horizon", "a positive number of seconds", fmt::format("{}", options_.horizon));
  }
  max_steps_ = static_cast<int>(std::floor(options_.horizon / options_.control_dt + 1e-9));
  monitor_ = sim::SeparationMonitor::FromModel(*model_);
  scratch_ = std::make_unique<Scratch>();
  if (policy_.cameras.empty()) return;
  if (options_.render_backend == render::Backend::kNone) {
    throw core::InputError("policy " + setup_.policy, "a renderer for its cameras (osmesa or egl)",
                           "render back end none");
  }
  for (const policy::CameraRequest& request : policy_.cameras) {
    scratch_->camera_ids.push_back(
        render::camera_id(*model_->m(), request.name, "policy " + setup_.policy + " camera"));
    scratch_->renderer_of.push_back(
        scene_ != nullptr
            ? &scene_->renderer(options_.render_backend, request.width, request.height)
            : &renderer_in(scratch_->renderers, options_.render_backend, *model_->m(), request.width, request.height));
  }
}

void Episode::reset() {
  const model::Model& model = *model_;
  sim::Data& data = *data_;
  log_ = EpisodeLog{};
  log_.task = setup_.task;
  log_.role = setup_.role;
  log_.spec_hash = setup_.spec_hash;
  log_.seed = setup_.seed;
  log_.policy = setup_.policy;
  log_.robot = model_->robot.name;
  log_.horizon = options_.horizon;
  log_.control_dt = options_.control_dt;
  log_.action_space = policy_.action_space;
  for (const model::ObjectInfo& object : model.objects) log_.object_names.push_back(object.name);
  log_.predicate_names = driver_->predicate_names();
  steps_ = 0;
  started_ = true;
  done_ = false;
  end_info_.clear();
  success_since_.reset();
  sim::reset(model, data);
  driver_->reset(model, data);
  sim::forward(model, data);
  for (EpisodeObserver* o : observers_) o->on_start(*this);
  record(nullptr);
}

void Episode::record(const policy::Action* action) {
  const model::Model& model = *model_;
  sim::Data& data = *data_;
  const mjModel& m = *model.m();
  const mjData& d = *data.mj;
  StepRecord s;
  s.time = data.time();
  const sim::ArmVector q = sim::arm_joint_positions(model, data);
  s.joint_pos.assign(q.begin(), q.end());
  const sim::ArmVector qd = sim::arm_joint_velocities(model, data);
  s.joint_vel.assign(qd.begin(), qd.end());
  s.X_WT = sim::observed_tcp_pose(model, data);
  s.gripper_width = sim::gripper_width(model, data);
  for (size_t f = 0; f < 2; ++f) s.finger_pos[f] = d.qpos[model.finger_qpos_adr[f]];
  if (action != nullptr) s.action = *action;
  s.joint_target.assign(data.q_target.begin(), data.q_target.end());
  s.gripper_target = data.gripper_width_target;
  if (model.has_human) {
    for (int j = 0; j < human::kNumJoints; ++j) {
      s.human_joints_W[static_cast<size_t>(j)] = data.X_WJ[static_cast<size_t>(j)].translation;
    }
    s.human_pose = data.human_pose;
  }
  for (const model::ObjectInfo& object : model.objects) {
    s.object_poses.push_back(body_pose(d, object.body));
    s.lid_angles.push_back(object.lid_joint >= 0 ? d.qpos[m.jnt_qposadr[object.lid_joint]] : 0.0);
  }
  // d(t) and the velocity of the robot's closest point.
  const sim::Separation sep = sim::min_separation(monitor_, data);
  s.separation = sep.distance;
  const sim::RobotPointMotion motion = sim::robot_point_motion(m, d, sep);
  s.approach_speed = motion.speed_toward_human;
  s.closest_point_speed = motion.velocity_W.norm();
  sim::find_contacts(model, data, &scratch_->contacts);
  s.contacts = robot_contacts(model, scratch_->contacts, scratch_->pairs);
  driver_->observe(model, data, s.predicates, log_.events);
  const std::optional<size_t> success = log_.predicate_index("success");
  if (success && *success < s.predicates.size() && s.predicates[*success]) {
    if (!success_since_) success_since_ = s.time;
  } else {
    success_since_.reset();
  }
  log_.steps.push_back(std::move(s));
  for (EpisodeObserver* o : observers_) o->on_step(*this, log_.steps.back());
}

void Episode::finish(core::EpisodeStatus status, std::string reason) {
  done_ = true;
  log_.status = status;
  log_.status_reason = status == core::EpisodeStatus::kOk ? "" : reason;
  end_info_ = std::move(reason);
  for (EpisodeObserver* o : observers_) o->on_end(*this);
}

void Episode::end(core::EpisodeStatus status, std::string reason) {
  check_running("end");
  finish(status, std::move(reason));
}

void Episode::check_running(std::string_view what) const {
  if (!started_) {
    throw core::InputError("Episode::" + std::string(what), "an episode started by reset()",
                           "an episode never reset");
  }
  if (done_) {
    const StepRecord& last = log_.steps.back();
    throw core::InputError(
        "Episode::" + std::string(what), "a running episode (reset() starts it again)",
        fmt::format("an episode that ended at {:.2f} s ({}{})", last.time,
                    core::to_string(log_.status), end_info_.empty() ? "" : ": " + end_info_));
  }
}

void Episode::check_action(const policy::Action& action, std::string_view where) const {
  policy::ActionChunk chunk{policy_.action_space, {action}};
  try {
    policy::validate_chunk(chunk, policy_.action_space, action_limits());
  } catch (const policy::PolicyError& e) {
    throw core::InputError::Message(std::string(where), e.what());
  }
}

bool Episode::advance(const policy::Action* action) {
  check_running(action != nullptr ? "step" : "hold");
  const model::Model& model = *model_;
  sim::Data& data = *data_;
  if (action != nullptr) {
    const policy::Action& a = *action;
    if (policy_.action_space == policy::ActionSpace::kEeDelta) {
      sim::EeDelta delta;
      delta.translation = core::Vec3(a[0], a[1], a[2]);
      delta.rotation = core::Vec3(a[3], a[4], a[5]);
      sim::apply_ee_delta(model, data, delta, sim::observed_tcp_pose(model, data));
    } else {
      sim::ArmVector q(model.robot.dof());
      std::copy_n(a.begin(), q.size(), q.begin());
      sim::set_joint_targets(model, data, q);
    }
    sim::set_gripper_width(model, data, a.back() * model.robot.gripper.max_width());
  }
  for (int i = 0; i < substeps_; ++i) {
    if (options_.person_pose_per_physics_step) {
      driver_->drive(model, data);
    } else {
      driver_->drive_between(model, data, i, substeps_);
    }
    sim::prepare_step(model, data);
    for (EpisodeObserver* o : observers_) o->on_physics_step(*this);
    mj_step(model.m(), data.mj.get());
  }
  if (options_.forward_after_control_step) {
    sim::forward(model, data);
  } else {
    sim::observe_state(model, data);
  }
  ++steps_;
  record(action);
  if (sim::warning_count(data) > 0) {
    finish(core::EpisodeStatus::kInvalid, "MuJoCo warning: " + sim::warning_summary(data));
  } else if (options_.stop_on_success && success_since_ &&
             log_.steps.back().time - *success_since_ >=
                 options_.constants.success_hold - options_.constants.time_epsilon) {
    finish(core::EpisodeStatus::kOk, "success held");
  } else if (steps_ >= max_steps_) {
    finish(core::EpisodeStatus::kOk, "horizon");
  }
  return done_;
}

StepResult Episode::result() {
  StepResult r;
  r.observation = observe();
  r.done = done_;
  r.status = log_.status;
  r.info = done_ ? end_info_ : "";
  return r;
}

StepResult Episode::step(const policy::Action& action) {
  check_running("step");
  check_action(action, "Episode::step action");
  advance(&action);
  return result();
}

StepResult Episode::step(const policy::ActionChunk& chunk) {
  check_running("step");
  if (chunk.space != policy_.action_space) {
    throw core::InputError("Episode::step chunk",
                           fmt::format("{} actions (the episode's action space)", policy::to_string(policy_.action_space)),
                           fmt::format("{} actions", policy::to_string(chunk.space)));
  }
  if (chunk.actions.empty()) {
    throw core::InputError("Episode::step chunk", "at least one action", "an empty chunk");
  }
  for (size_t i = 0; i < chunk.actions.size(); ++i) {
    check_action(chunk.actions[i], fmt::format("Episode::step chunk action {}", i));
  }
  for (const policy::Action& action : chunk.actions) {
    if (advance(&action)) break;
  }
  return result();
}

StepResult Episode::hold() {
  advance(nullptr);
  return result();
}

policy::Observation Episode::observe() {
  if (!started_) check_running("observe");
  const StepRecord& s = log_.steps.back();
  policy::Observation obs;
  obs.time = s.time;
  obs.instruction = setup_.instruction;
  obs.proprio.joint_pos = model::JointVector(s.joint_pos.size());
  std::copy(s.joint_pos.begin(), s.joint_pos.end(), obs.proprio.joint_pos.begin());
  obs.proprio.joint_vel = model::JointVector(s.joint_vel.size());
  std::copy(s.joint_vel.begin(), s.joint_vel.end(), obs.proprio.joint_vel.begin());
  obs.proprio.gripper_width = s.gripper_width;
  obs.proprio.X_WT = s.X_WT;
  if (policy_.state_track) {
    policy::StateObservation state;
    state.human_joints_W = s.human_joints_W;
    for (size_t i = 0; i < model_->objects.size(); ++i) {
      state.objects.push_back({model_->objects[i].name, s.object_poses[i]});
    }
    std::sort(state.objects.begin(), state.objects.end(),
              [](const policy::ObjectPose& a, const policy::ObjectPose& b) { return a.name < b.name; });
    obs.state = std::move(state);
  }
  for (size_t i = 0; i < scratch_->camera_ids.size(); ++i) {
    policy::Image image;
    image.camera = policy_.cameras[i].name;
    render::Image rgb;
    scratch_->renderer_of[i]->render(*model_, *data_, scratch_->camera_ids[i], rgb);
    image.width = rgb.width;
    image.height = rgb.height;
    image.pixels = std::move(rgb.rgb);
    obs.images.push_back(std::move(image));
  }
  if (policy_.privileged) {
    for (const Event& event : log_.events) {
      obs.events.push_back({event.time, std::string(to_string(event.kind)), event.name, event.detail});
    }
  }
  return obs;
}

EpisodeMetrics Episode::metrics() const {
  if (!contract_) {
    throw core::InputError("Episode::metrics", "an episode made from an EpisodeSpec (its contract)",
                           "an episode of a bare scenario driver");
  }
  return compute_metrics(*contract_, log_, options_.constants);
}

policy::EpisodeInfo Episode::info() const {
  return {setup_.task,         setup_.instruction, setup_.seed, options_.horizon, options_.control_dt,
          model_->robot.name, policy_.privileged ? driver_->episode() : nullptr};
}

policy::ActionLimits Episode::action_limits() const { return policy::action_limits(model_->robot); }

void Episode::add_observer(EpisodeObserver& observer) { observers_.push_back(&observer); }

void Episode::remove_observer(EpisodeObserver& observer) {
  observers_.erase(std::remove(observers_.begin(), observers_.end(), &observer), observers_.end());
}

EpisodeSnapshot Episode::snapshot() const {
  std::unique_ptr<ScenarioDriver> driver = driver_->clone();
  if (!driver) {
    throw core::InputError("Episode::snapshot", "a scenario driver that can be copied (clone)",
                           "a driver without clone()");
  }
  EpisodeSnapshot s;
  s.spec_hash_ = setup_.spec_hash;
  s.model_ = model_;
  s.data_ = std::make_unique<sim::Data>(sim::make_data(*model_));
  sim::copy_data(*model_, *data_, *s.data_);
  s.driver_ = std::move(driver);
  s.log_ = log_;
  s.steps_ = steps_;
  s.started_ = started_;
  s.done_ = done_;
  s.end_info_ = end_info_;
  s.success_since_ = success_since_;
  return s;
}

void Episode::restore(const EpisodeSnapshot& s) {
  if (s.spec_hash_ != setup_.spec_hash || s.model_->m()->nq != model_->m()->nq ||
      s.model_->objects.size() != model_->objects.size()) {
    throw core::InputError("Episode::restore", "a snapshot of spec " + setup_.spec_hash,
                           "a snapshot of spec " + s.spec_hash_);
  }
  sim::copy_data(*model_, *s.data_, *data_);
  own_driver_ = s.driver_->clone();
  driver_ = own_driver_.get();
  log_ = s.log_;
  steps_ = s.steps_;
  started_ = s.started_;
  done_ = s.done_;
  end_info_ = s.end_info_;
  success_since_ = s.success_since_;
}

EpisodeSnapshot::EpisodeSnapshot(const EpisodeSnapshot& other)
    : spec_hash_(other.spec_hash_),
      model_(other.model_),
      data_(std::make_unique<sim::Data>(sim::make_data(*other.model_))),
      driver_(other.driver_->clone()),
      log_(other.log_),
      steps_(other.steps_),
      started_(other.started_),
      done_(other.done_),
      end_info_(other.end_info_),
      success_since_(other.success_since_) {
  sim::copy_data(*model_, *other.data_, *data_);
}
EpisodeSnapshot::EpisodeSnapshot(EpisodeSnapshot&&) noexcept = default;
EpisodeSnapshot::~EpisodeSnapshot() = default;

double EpisodeSnapshot::time() const { return data_->time(); }

void LogFileWriter::on_end(const Episode& episode) { save_episode_log(episode.log(), path_); }

void pose_from_step(const model::Model& model, const EpisodeLog& log, const StepRecord& s,
                    sim::Data& data) {
  const mjModel& m = *model.m();
  mjData& d = *data.mj;
  const size_t dof = model.robot.dof();
  if (s.joint_pos.size() != dof ||
      log.object_names.size() != model.objects.size() || s.object_poses.size() != model.objects.size() ||
      s.lid_angles.size() != model.objects.size()) {
    throw core::InputError("pose_from_step",
                           fmt::format("a step of this model ({} arm joints, {} objects)", dof, model.objects.size()),
                           fmt::format("{} arm joints, {} objects", s.joint_pos.size(), s.object_poses.size()));
  }
  for (size_t i = 0; i < model.objects.size(); ++i) {
    if (log.object_names[i] != model.objects[i].name) {
      throw core::InputError("pose_from_step object " + std::to_string(i), model.objects[i].name, log.object_names[i]);
    }
  }
  d.time = s.time;
  for (size_t j = 0; j < dof; ++j) {
    d.qpos[model.arm_qpos_adr[j]] = s.joint_pos[j];
    d.qvel[model.arm_dof_adr[j]] = s.joint_vel.size() > j ? s.joint_vel[j] : 0.0;
  }
  for (size_t f = 0; f < 2; ++f) d.qpos[model.finger_qpos_adr[f]] = s.finger_pos[f];
  for (size_t i = 0; i < model.objects.size(); ++i) {
    const model::ObjectInfo& object = model.objects[i];
    mjtNum* q = d.qpos + object.qpos_adr;
    const core::Pose& X = s.object_poses[i];
    q[0] = X.translation.x();
    q[1] = X.translation.y();
    q[2] = X.translation.z();
    q[3] = X.rotation.w();
    q[4] = X.rotation.x();
    q[5] = X.rotation.y();
    q[6] = X.rotation.z();
    if (object.lid_joint >= 0) d.qpos[m.jnt_qposadr[object.lid_joint]] = s.lid_angles[i];
  }
  if (model.has_human) sim::set_human_pose(model, data, s.human_pose);
  sim::forward(model, data);
}

}  // namespace hribench::eval
