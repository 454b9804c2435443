#include "eval/runner.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <fmt/format.h>
#include <optional>
#include <tuple>

#include <mujoco/mujoco.h>

#include "core/errors.h"
#include "eval/metrics.h"
#include "render/renderer.h"
#include "sim/contact.h"
#include "sim/control.h"
#include "sim/separation.h"

namespace hribench::eval {

Latency parse_latency(std::string_view text) {
  if (text == "none") return {LatencyMode::kNone, 0};
  if (text == "measured") return {LatencyMode::kMeasured, 0};
  if (text.substr(0, 6) == "fixed:") {
    // A finite delay of at most a minute (longer is no interaction, and would overflow the
    // control-step count).
    const std::string ms(text.substr(6));
    char* end = nullptr;
    const double value = std::strtod(ms.c_str(), &end);
    if (ms.empty() || end != ms.c_str() + ms.size() || !std::isfinite(value) || value < 0 ||
        value > kMaxFixedLatencyMs) {
      throw core::InputError("--latency",
                             fmt::format("fixed:MS with MS milliseconds in [0, {}]", kMaxFixedLatencyMs),
                             "'" + std::string(text) + "'");
    }
    return {LatencyMode::kFixed, value / 1000.0};
  }
  throw core::InputError("--latency", "none, fixed:MS (milliseconds >= 0) or measured",
                         "'" + std::string(text) + "'");
}

std::string to_string(const Latency& latency) {
  switch (latency.mode) {
    case LatencyMode::kNone:
      return "none";
    case LatencyMode::kFixed:
      return fmt::format("fixed:{}", latency.fixed_seconds * 1000.0);
    case LatencyMode::kMeasured:
      return "measured";
  }
  return "unknown";
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

// Everything one episode keeps between control steps (allocated once).
struct Episode {
  const model::Model& model;
  sim::Data& data;
  sim::SeparationMonitor monitor;
  std::vector<sim::Contact> contacts;
  std::vector<ContactPair> pairs;  // scratch of robot_contacts
};

core::Pose body_pose(const mjData& d, int body) {
  core::Pose pose;
  pose.translation = core::Vec3(d.xpos[3 * body], d.xpos[3 * body + 1], d.xpos[3 * body + 2]);
  pose.rotation = core::quat_from_wxyz(d.xquat + 4 * body);
  return pose;
}

StepRecord record_step(Episode& e) {
  const model::Model& model = e.model;
  sim::Data& data = e.data;
  const mjModel& m = *model.m();
  const mjData& d = *data.mj;
  StepRecord s;
  s.time = data.time();
  const sim::ArmVector q = sim::arm_joint_positions(model, data);
  s.joint_pos.assign(q.begin(), q.end());
  s.X_WE = sim::tcp_pose(model, data);
  s.gripper_width = sim::gripper_width(model, data);
  if (model.has_human) {
    for (int j = 0; j < human::kNumJoints; ++j) s.human_joints_W[static_cast<size_t>(j)] = data.X_WJ[static_cast<size_t>(j)].translation;
  }
  for (const model::ObjectInfo& object : model.objects) s.object_poses.push_back(body_pose(d, object.body));
  // d(t) and the velocity of the robot's closest point.
  const sim::Separation sep = sim::min_separation(e.monitor, data);
  s.separation = sep.distance;
  const sim::RobotPointMotion motion = sim::robot_point_motion(m, d, sep);
  s.approach_speed = motion.speed_toward_human;
  s.closest_point_speed = motion.velocity_W.norm();
  sim::find_contacts(model, data, &e.contacts);
  s.contacts = robot_contacts(model, e.contacts, e.pairs);
  return s;
}

// One renderer per requested camera, for this episode's model.
struct Cameras {
  std::vector<std::unique_ptr<render::Renderer>> renderers;
  std::vector<int> ids;
};

Cameras make_cameras(const model::Model& model, const policy::PolicySpec& spec,
                     const std::string& policy_name, render::Backend backend) {
  Cameras cameras;
  if (spec.cameras.empty()) return cameras;
  if (backend == render::Backend::kNone) {
    throw core::InputError("policy " + policy_name, "a renderer for its cameras (osmesa or egl)",
                           "render back end none");
  }
  for (const policy::CameraRequest& request : spec.cameras) {
    cameras.ids.push_back(render::camera_id(*model.m(), request.name, "policy " + policy_name + " camera"));
    cameras.renderers.push_back(render::make_renderer(backend, *model.m(), request.width, request.height));
  }
  return cameras;
}

policy::Observation observe(const Episode& e, const policy::PolicySpec& spec,
                            const std::string& instruction, const StepRecord& s,
                            Cameras& cameras, const std::vector<Event>& events) {
  policy::Observation obs;
  obs.time = s.time;
  obs.instruction = instruction;
  obs.proprio.joint_pos = sim::arm_joint_positions(e.model, e.data);
  obs.proprio.joint_vel = sim::arm_joint_velocities(e.model, e.data);
  obs.proprio.gripper_width = s.gripper_width;
  obs.proprio.X_WT = s.X_WE;
  if (spec.state_track) {
    policy::StateObservation state;
    state.human_joints_W = s.human_joints_W;
    for (size_t i = 0; i < e.model.objects.size(); ++i) {
      state.objects.push_back({e.model.objects[i].name, s.object_poses[i]});
    }
    std::sort(state.objects.begin(), state.objects.end(),
              [](const policy::ObjectPose& a, const policy::ObjectPose& b) { return a.name < b.name; });
    obs.state = std::move(state);
  }
  for (size_t i = 0; i < cameras.renderers.size(); ++i) {
    policy::Image image;
    image.camera = spec.cameras[i].name;
    render::Image rgb;
    cameras.renderers[i]->render(e.model, e.data, cameras.ids[i], rgb);
    image.width = rgb.width;
    image.height = rgb.height;
    image.pixels = std::move(rgb.rgb);
    obs.images.push_back(std::move(image));
  }
  if (spec.privileged) {
    for (const Event& event : events) {
      obs.events.push_back({event.time, std::string(to_string(event.kind)), event.name, event.detail});
    }
  }
  return obs;
}

void apply_action(const model::Model& model, sim::Data& data, policy::ActionSpace space,
                  const policy::Action& a) {
  if (space == policy::ActionSpace::kEeDelta) {
    sim::EeDelta delta;
    delta.translation = core::Vec3(a[0], a[1], a[2]);
    delta.rotation = core::Vec3(a[3], a[4], a[5]);
    sim::apply_ee_delta(model, data, delta);
  } else {
    sim::ArmVector q(model.robot.dof());
    std::copy_n(a.begin(), q.size(), q.begin());
    sim::set_joint_targets(model, data, q);
  }
  sim::set_gripper_width(model, data, a.back() * model.robot.gripper.max_width());
}

}  // namespace

EpisodeLog run_episode(const model::Model& model, sim::Data& data, policy::Policy& policy,
                       ScenarioDriver& driver, const EpisodeSetup& setup,
                       const RunOptions& options) {
  const double physics_per_control = options.control_dt / model::kTimestep;
  const int substeps = static_cast<int>(std::lround(physics_per_control));
  if (substeps < 1 || std::abs(physics_per_control - substeps) > 1e-9) {
    throw core::InputError("control_dt", "a whole number of 2 ms physics steps",
                           fmt::format("{} s", options.control_dt));
  }
  if (!(options.horizon > 0)) {
    throw core::InputError("horizon", "a positive number of seconds", fmt::format("{}", options.horizon));
  }
  const policy::PolicySpec spec = policy.spec();
  const policy::ActionLimits limits = policy::action_limits(model.robot);
  Cameras cameras = make_cameras(model, spec, setup.policy, options.render_backend);
  const double eps = options.constants.time_epsilon;

  EpisodeLog log;
  log.task = setup.task;
  log.role = setup.role;
  log.spec_hash = setup.spec_hash;
  log.seed = setup.seed;
  log.policy = setup.policy;
  log.horizon = options.horizon;
  log.control_dt = options.control_dt;
  for (const model::ObjectInfo& object : model.objects) log.object_names.push_back(object.name);
  log.predicate_names = driver.predicate_names();

  sim::reset(model, data);
  driver.reset(model, data);
  sim::forward(model, data);
  Episode e{model, data, sim::SeparationMonitor::FromModel(model), {}, {}};
  // Ends the episode with a status other than ok.
  const auto end_with = [&](core::EpisodeStatus status, std::string reason) {
    log.status = status;
    log.status_reason = std::move(reason);
  };
  // Start of the current run of "success" steps (what final_run_start would say), kept as the
  // steps come so the stop check does not rescan the log.
  const std::optional<size_t> success_index = log.predicate_index("success");
  std::optional<double> success_since;
  // Records the current state as a step.
  const auto record = [&] {
    StepRecord s = record_step(e);
    driver.observe(model, data, s.predicates, log.events);
    if (success_index && *success_index < s.predicates.size() && s.predicates[*success_index]) {
      if (!success_since) success_since = s.time;
    } else {
      success_since.reset();
    }
    log.steps.push_back(std::move(s));
  };
  // True once "success" has held for constants.success_hold up to the last step.
  const auto success_held = [&] {
    return success_since &&
           log.steps.back().time - *success_since >= options.constants.success_hold - eps;
  };

  policy::EpisodeInfo info{setup.task, setup.instruction, setup.seed, options.horizon,
                           options.control_dt, model.robot.name,
                           spec.privileged ? driver.episode() : nullptr};
  try {
    policy.reset(info);
  } catch (const std::exception& ex) {
    record();
    end_with(core::EpisodeStatus::kPolicyError, std::string("reset: ") + ex.what());
    return log;
  }
  record();

  std::deque<policy::Action> queue;   // actions to execute, one per control step
  std::vector<policy::Action> pending;  // a chunk that arrives when thinking ends
  int thinking = 0;                      // control steps left until `pending` arrives
  const int steps = static_cast<int>(std::floor(options.horizon / options.control_dt + 1e-9));
  for (int k = 0; k < steps; ++k) {
    // Ask the policy when nothing is queued or on the way.
    if (queue.empty() && thinking == 0) {
      const policy::Observation obs = observe(e, spec, setup.instruction, log.steps.back(), cameras, log.events);
      policy::ActionChunk chunk;
      const auto start = std::chrono::steady_clock::now();
      try {
        chunk = policy.act(obs);
        policy::validate_chunk(chunk, spec.action_space, limits);
      } catch (const std::exception& ex) {
        end_with(core::EpisodeStatus::kPolicyError, ex.what());
        return log;
      }
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double delay = options.latency.mode == LatencyMode::kNone    ? 0.0
                           : options.latency.mode == LatencyMode::kFixed ? options.latency.fixed_seconds
                                                                         : wall;
      const size_t take = std::min(chunk.actions.size(), static_cast<size_t>(std::max(1, spec.replan_every)));
      chunk.actions.resize(take);
      thinking = static_cast<int>(std::ceil(delay / options.control_dt - 1e-9));
      if (thinking == 0) {
        queue.assign(chunk.actions.begin(), chunk.actions.end());
      } else {
        pending = std::move(chunk.actions);
      }
    }
    // Thinking: the previous command stays; otherwise execute the next action.
    if (thinking > 0) {
      if (--thinking == 0) queue.assign(pending.begin(), pending.end());
    } else {
      apply_action(model, data, spec.action_space, queue.front());
      queue.pop_front();
    }
    for (int i = 0; i < substeps; ++i) {
      driver.drive(model, data);
      sim::step(model, data);
    }
    sim::forward(model, data);
    if (sim::warning_count(data) > 0) {
      record();
      end_with(core::EpisodeStatus::kInvalid, "MuJoCo warning: " + sim::warning_summary(data));
      return log;
    }
    record();
    if (options.stop_on_success && success_held()) break;
  }
  return log;
}

}  // namespace hribench::eval
