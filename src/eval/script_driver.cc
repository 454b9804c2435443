#include "eval/script_driver.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/errors.h"
#include "human/arm_ik.h"
#include "human/clip_io.h"
#include "human/primitives.h"
#include "sim/contact.h"
#include "sim/control.h"
#include "sim/hold.h"

namespace hribench::eval {
namespace {

constexpr double kDegToRad = core::kPi / 180;

std::string object_where(const std::string& name) { return "scene.objects." + name; }

const script::Entry<script::SceneObject>* find_object(const script::EpisodeSpec& spec,
                                                       const std::string& name) {
  for (const script::Entry<script::SceneObject>& o : spec.scene.objects) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

// Footprint x/y of an object from its pose, or its container's (nullopt: neither).
std::optional<std::pair<double, double>> footprint(const script::EpisodeSpec& spec,
                                                    const script::SceneObject& object, int depth) {
  if (object.pose && object.pose->xy.size() == 2) {
    return std::make_pair(object.pose->xy[0].value(), object.pose->xy[1].value());
  }
  if (object.in && depth < 8) {
    const script::Entry<script::SceneObject>* container = find_object(spec, object.in->value());
    if (container != nullptr) return footprint(spec, container->value, depth + 1);
  }
  return std::nullopt;
}

// Pose of an object's bounding-box centre from its freejoint state (always current).
core::Pose object_centre_pose(const model::Model& model, const sim::Data& data, size_t object) {
  const model::ObjectInfo& info = model.objects[object];
  const mjtNum* q = data.mj->qpos + info.qpos_adr;
  core::Pose X_WB{core::quat_from_wxyz(q + 3).normalized(), core::Vec3(q[0], q[1], q[2])};
  core::Pose X_BC;
  X_BC.translation = core::Vec3(0, 0, info.half_extents.z());
  return X_WB * X_BC;
}

const human::Joint kWrist[2] = {human::Joint::kLeftWrist, human::Joint::kRightWrist};

const human::Joint kLegs[] = {human::Joint::kLeftHip,   human::Joint::kRightHip,  human::Joint::kLeftKnee,
                              human::Joint::kRightKnee, human::Joint::kLeftAnkle, human::Joint::kRightAnkle,
                              human::Joint::kLeftFoot,  human::Joint::kRightFoot};

// Whether a plan moves the body's root: a walking segment or a stand frame that moves.
bool moves_root(const human::MotionPlan& plan) {
  const core::Vec3 start = plan.key_at(0).X_WF.translation;
  for (const human::Segment& segment : plan.segments()) {
    if (segment.walking || (segment.end.X_WF.translation - start).norm() > 0.01) return true;
  }
  return false;
}

// A hand takes an object the way its kind is held: a box by its lid (hold_lid), a plank by
// the point under the palm (both hands at one end), anything else whole.
void grasp(const model::Model& model, sim::Data& data, human::Side side, int object) {
  const model::ObjectKind kind = model.objects[static_cast<size_t>(object)].kind;
  if (kind == model::ObjectKind::kBox) {
    sim::grasp_lid_by_human(model, data, side, object);
  } else if (kind == model::ObjectKind::kPlank) {
    sim::grasp_point_by_human(model, data, side, object);
  } else {
    sim::grasp_by_human(model, data, side, object);
  }
}

// Whether a plan moves hand h: a palm target or grip that changes, a via-point, or walking.
bool moves_hand(const human::MotionPlan& plan, size_t h) {
  const human::HandKey start = plan.key_at(0).hands[h];
  for (const human::Segment& segment : plan.segments()) {
    const human::HandKey& end = segment.end.hands[h];
    if (segment.walking || !segment.via[h].empty() || (end.palm - start.palm).norm() > 1e-3 ||
        end.grip != start.grip || end.holding != start.holding) {
      return true;
    }
  }
  return false;
}
const human::Side kSides[2] = {human::Side::kLeft, human::Side::kRight};

}  // namespace

model::SceneSpec scene_spec_from_episode(const script::EpisodeSpec& spec) {
  model::SceneSpec scene;
  scene.robot = spec.robot;
  scene.objects.clear();
  // Platforms first (objects may rest on them).
  for (const script::Entry<script::SceneObject>& entry : spec.scene.objects) {
    const script::SceneObject& o = entry.value;
    if (o.kind.value() != "platform") continue;
    const std::string where = object_where(entry.name);
    if (o.size.size() != 3 || !o.pose || o.pose->xy.size() != 2) {
      throw core::InputError::Message(where, "a platform needs a size [x, y, z] and a pose xy");
    }
    model::PlatformSpec platform;
    platform.name = entry.name;
    platform.x = o.pose->xy[0].value();
    platform.y = o.pose->xy[1].value();
    platform.yaw = o.pose->yaw_deg.value() * kDegToRad;
    platform.length = o.size[0].value();
    platform.width = o.size[1].value();
    platform.height = o.size[2].value();
    scene.platforms.push_back(platform);
  }
  for (const script::Entry<script::SceneObject>& entry : spec.scene.objects) {
    const script::SceneObject& o = entry.value;
    const std::string where = object_where(entry.name);
    const std::string& kind = o.kind.value();
    if (kind == "platform") continue;
    if (!model::object_kind_from_name(kind)) {
      throw core::InputError(where, "an object kind the model builds (cube, cup, bottle, plate, bin, tray, box, plank, platform)", kind);
    }
    if (!o.size.empty()) {
      throw core::InputError::Message(where, "an explicit size is not supported by the model (only the kind's size)");
    }
    model::ObjectSpec object;
    object.kind = kind;
    object.name = entry.name;
    if (o.color) object.colour = o.color->value() == "gray" ? "grey" : o.color->value();
    if (o.held_by) {
      const std::string& hand = o.held_by->value();
      if (hand == "human.left") {
        object.held_by = human::Side::kLeft;
      } else if (hand == "human.right") {
        object.held_by = human::Side::kRight;
      } else {
        throw core::InputError(where + ".held_by", "human.left or human.right", hand);
      }
    } else {
      const std::optional<std::pair<double, double>> xy = footprint(spec, o, 0);
      if (!xy) throw core::InputError::Message(where, "needs a pose, a container (in) or a hand (held_by)");
      object.x = xy->first;
      object.y = xy->second;
      if (o.in && !(o.pose && o.pose->xy.size() == 2)) object.inside = o.in->value();
      // A centre height above the table: resting on the platform under it.
      if (o.pose && o.pose->z) {
        for (const model::PlatformSpec& platform : scene.platforms) {
          const Eigen::Vector2d q = Eigen::Rotation2Dd(-platform.yaw) *
                                    Eigen::Vector2d(object.x - platform.x, object.y - platform.y);
          if (std::abs(q.x()) <= platform.length / 2 && std::abs(q.y()) <= platform.width / 2) {
            object.on = platform.name;
            break;
          }
        }
        if (object.on.empty()) {
          throw core::InputError::Message(where + ".pose.z", "a height is only supported over a platform (the object rests on it)");
        }
      }
    }
    if (o.pose) object.yaw = o.pose->yaw_deg.value() * kDegToRad;
    scene.objects.push_back(object);
  }
  scene.human.height = spec.human.height.value();
  scene.human.x = spec.human.stand.x.value();
  scene.human.y = spec.human.stand.y.value();
  scene.human.yaw = spec.human.stand.yaw_deg.value() * kDegToRad;
  scene.human.handedness =
      spec.human.handedness.value() == "left" ? human::Side::kLeft : human::Side::kRight;
  return scene;
}

human::PrimitiveParams primitive_params(
    const script::EpisodeSpec& spec, size_t act,
    const std::function<core::Vec3(const std::string&)>& object_centre) {
  HRIB_CHECK(act < spec.acts.size()) << act;
  const script::Entry<script::Act>& entry = spec.acts[act];
  const std::string where = "acts." + entry.name + ".motion";
  if (!entry.value.motion || !entry.value.motion->primitive) {
    throw core::InputError::Message(where, "no primitive motion to plan");
  }
  const script::Motion& motion = *entry.value.motion;
  human::PrimitiveParams p;
  p.primitive = motion.primitive->value();
  p.seed = spec.seed * 1000003ULL + act;
  const human::PrimitiveInfo* info = human::find_primitive(p.primitive);
  if (info == nullptr) throw core::InputError(where + ".primitive", "a catalog primitive", p.primitive);
  // A point: an object's centre (name) or [x, y, z].
  const auto point = [&](const script::ValueTree& t) {
    if (t.kind == script::ValueTree::Kind::kScalar) return object_centre(t.scalar.expr.text);
    if (t.items.size() != 3) throw core::InputError::Message(where, "a point needs [x, y, z]");
    return core::Vec3(t.items[0].scalar.expr.number, t.items[1].scalar.expr.number,
                      t.items[2].scalar.expr.number);
  };
  for (const script::Entry<script::ValueTree>& e : motion.params) {
    const script::ValueTree& v = e.value;
    const human::ParamInfo* param = info->param(e.name);
    if (param == nullptr) continue;  // script-level keys (onset) are not primitive parameters
    switch (param->kind) {
      case human::ParamKind::kNumber: p.numbers[e.name] = v.scalar.expr.number; break;
      case human::ParamKind::kSide:
      case human::ParamKind::kChoice: p.choices[e.name] = v.scalar.expr.text; break;
      case human::ParamKind::kPoint: p.points[e.name] = point(v); break;
      case human::ParamKind::kPoints:
        for (const script::ValueTree& item : v.items) p.paths[e.name].push_back(point(item));
        break;
      case human::ParamKind::kZone:
        for (size_t i = 0; i < v.keys.size() && i < v.items.size(); ++i) {
          if (v.keys[i] == "center") p.zones[e.name].center = point(v.items[i]);
          if (v.keys[i] == "radius") p.zones[e.name].radius = v.items[i].scalar.expr.number;
        }
        break;
      case human::ParamKind::kObject: p.objects[e.name] = v.scalar.expr.text; break;
    }
  }
  return p;
}

ScriptDriver::ScriptDriver(script::EpisodeSpec spec)
    : ScriptDriver(std::make_shared<const script::EpisodeSpec>(std::move(spec))) {}

ScriptDriver::ScriptDriver(std::shared_ptr<const script::EpisodeSpec> spec)
    : script_(compile(std::move(spec))), runtime_(script::make_runtime(script_->graph)) {}

std::shared_ptr<const ScriptDriver::Script> ScriptDriver::compile(
    std::shared_ptr<const script::EpisodeSpec> spec) {
  auto compiled = std::make_shared<Script>();
  compiled->graph = script::compile(*spec);
  compiled->spec = std::move(spec);
  const script::ActGraph& graph_ = compiled->graph;
  std::vector<EventInfo>& event_info_ = compiled->event_info;
  std::vector<std::string>& predicate_names_ = compiled->predicate_names;
  // What each event id means in the log.
  event_info_.resize(graph_.event_names.size());
  for (size_t i = 0; i < event_info_.size(); ++i) event_info_[i].name = graph_.event_names[i];
  const auto set = [&](int id, EventKind kind, Actor actor) {
    if (id < 0) return;
    event_info_[static_cast<size_t>(id)].kind = kind;
    event_info_[static_cast<size_t>(id)].actor = actor;
  };
  for (const script::CompiledAct& act : graph_.acts) {
    const Actor actor = act.human ? Actor::kHuman : Actor::kRobot;
    set(act.start_event, EventKind::kActStart, actor);
    set(act.end_event, EventKind::kActEnd, actor);
    set(act.skipped_event, EventKind::kWarning, actor);
    if (act.skipped_event >= 0) event_info_[static_cast<size_t>(act.skipped_event)].detail = "skipped";
    for (const script::CompiledPhase& phase : act.phases) set(phase.event, EventKind::kPhase, actor);
    if (act.cue && act.cue->event >= 0) event_info_[static_cast<size_t>(act.cue->event)].cue_kind = act.cue->kind;
  }
  // CIR series when an act contradicts a robot act.
  predicate_names_ = {"success"};
  for (const script::CompiledAct& act : graph_.acts) {
    if (act.human && act.contradicts >= 0) {
      predicate_names_ = {"success", "intent", "contradicted"};
      break;
    }
  }
  for (size_t w = 0; w < graph_.watched.size(); ++w) {
    for (const auto& [id, truth] : {std::pair{graph_.watch_true_event[w], "true"},
                                    std::pair{graph_.watch_false_event[w], "false"}}) {
      if (id < 0) continue;
      EventInfo& info = event_info_[static_cast<size_t>(id)];
      info.kind = EventKind::kPredicateChange;
      info.detail = truth;
      const size_t colon = info.name.rfind(':');
      if (colon != std::string::npos) info.name = info.name.substr(0, colon);
    }
  }
  return compiled;
}

void ScriptDriver::reset(const model::Model& model, sim::Data& data) {
  script::reset(script_->graph, runtime_);
  motions_.assign(script_->graph.acts.size(), ActMotion{});
  active_ = -1;
  last_holding_ = {};
  holding_plan_ = {-1, -1};
  events_seen_ = 0;
  control_step_start_.reset();
  control_step_end_.reset();
  // Graph objects in the model: objects, or platforms (fixed).
  object_of_graph_.assign(script_->graph.objects.size(), -1);
  platform_of_graph_.assign(script_->graph.objects.size(), -1);
  world_.objects.assign(script_->graph.objects.size(), script::ObjectState{});
  for (size_t i = 0; i < script_->graph.objects.size(); ++i) {
    script::ObjectState& state = world_.objects[i];
    const int index = model.object_index(script_->graph.objects[i]);
    const int platform = model.platform_index(script_->graph.objects[i]);
    if (index >= 0) {
      object_of_graph_[i] = index;
      const size_t o = static_cast<size_t>(index);
      state.half_extents = model.objects[o].half_extents;
      state.p_WO_initial = object_centre_pose(model, data, o).translation;
    } else if (platform >= 0) {
      platform_of_graph_[i] = platform;
      const model::PlatformInfo& info = model.platforms[static_cast<size_t>(platform)];
      state.X_WO = info.X_WC;
      state.half_extents = info.half_extents;
      state.p_WO_initial = info.X_WC.translation;
    } else {
      throw core::InputError::Message(object_where(script_->graph.objects[i]),
                                      "not in the model (build it with scene_spec_from_episode)");
    }
  }
  p_WT_home_ = sim::tcp_pose(model, data).translation;
  world_.table_height = model::kTableTopZ;
}

std::optional<ScriptDriver::Posed> ScriptDriver::pose_at(const model::Model& model, double t) {
  if (active_ < 0 || !model.has_human) return std::nullopt;
  ActMotion& body = motions_[static_cast<size_t>(active_)];
  if (!body.playing()) return std::nullopt;
  const human::MotionPlan::Frame body_frame = body.frame_at(t - body.start);
  Posed posed;
  human::SkeletonPose& pose = posed.pose;
  pose = body_frame.pose;
  // A walk that an act started mid-way keeps going: the root and the legs follow the latest
  // started act that moves the root while its plan runs (the upper body rides along).
  int walker = -1;
  for (size_t i = 0; i < motions_.size(); ++i) {
    const ActMotion& m = motions_[i];
    if (!m.playing() || !m.moves_root || runtime_.acts[i].status != script::ActStatus::kRunning ||
        t - m.start >= m.end_time()) {
      continue;
    }
    if (walker < 0 || m.start >= motions_[static_cast<size_t>(walker)].start) walker = static_cast<int>(i);
  }
  if (walker >= 0 && walker != active_) {
    ActMotion& m = motions_[static_cast<size_t>(walker)];
    const human::SkeletonPose walk = m.frame_at(t - m.start).pose;
    pose.X_WP = walk.X_WP;
    for (const human::Joint j : kLegs) pose.local[static_cast<size_t>(human::index(j))] = walk.local[static_cast<size_t>(human::index(j))];
  }
  // Each hand follows the latest started act that moves it (a person holding a lid with one
  // hand while the other points); the rest of the body the latest started act.
  Holds& holds = posed.holds;
  holds.owner = hand_owners();
  for (size_t h = 0; h < 2; ++h) {
    if (holds.owner[h] == active_) {
      holds.labels[h] = body_frame.label;
      continue;
    }
    ActMotion& m = motions_[static_cast<size_t>(holds.owner[h])];
    const human::MotionPlan::Frame arm = m.frame_at(t - m.start);
    holds.labels[h] = arm.label;
    // The arm reaches where the owning plan puts the wrist (world pose), from this torso.
    pose.hands[h] = arm.pose.hands[h];
    const core::Pose X_WW = human::joint_pose(model.skeleton, arm.pose, kWrist[h]);
    human::ArmTarget target;
    target.wrist = X_WW.translation;
    target.hand = X_WW.rotation;
    target.swivel = arm.key.hands[h].swivel;
    human::solve_arm(model.skeleton, pose, kSides[h], target);
  }
  return posed;
}

std::array<int, 2> ScriptDriver::hand_owners() const {
  const ActMotion& body = motions_[static_cast<size_t>(active_)];
  std::array<int, 2> owner = {active_, active_};
  for (size_t h = 0; h < 2; ++h) {
    if (body.moves[h]) continue;
    for (size_t i = 0; i < motions_.size(); ++i) {
      const ActMotion& m = motions_[i];
      if (!m.playing() || !m.moves[h]) continue;
      if (owner[h] == active_ || m.start >= motions_[static_cast<size_t>(owner[h])].start) {
        owner[h] = static_cast<int>(i);
      }
    }
  }
  return owner;
}

std::optional<ScriptDriver::Holds> ScriptDriver::holds_at(const model::Model& model, double t) const {
  if (active_ < 0 || !model.has_human || !motions_[static_cast<size_t>(active_)].playing()) return std::nullopt;
  Holds holds;
  holds.owner = hand_owners();
  for (size_t h = 0; h < 2; ++h) {
    const ActMotion& m = motions_[static_cast<size_t>(holds.owner[h])];
    holds.labels[h] = m.label_at(t - m.start);
  }
  return holds;
}

void ScriptDriver::drive(const model::Model& model, sim::Data& data) {
  const std::optional<Posed> posed = pose_at(model, data.time());
  if (!posed) return;
  sim::set_human_pose(model, data, posed->pose);
  hold_as_labelled(model, data, posed->holds);
}

void ScriptDriver::drive_between(const model::Model& model, sim::Data& data, int step, int steps) {
  if (step == 0) {
    // The last control step's end is this one's start where nothing pose_at reads besides the
    // time changed since it was made (observe changes it when an act starts or ends, or a phase
    // signal arrives); otherwise both ends are made anew.
    const PlanInputs inputs = plan_inputs();
    if (control_step_end_ && control_step_end_time_ == data.time() && plan_inputs_ == inputs) {
      control_step_start_ = std::move(control_step_end_);
    } else {
      control_step_start_ = pose_at(model, data.time());
    }
    control_step_end_.reset();
    if (control_step_start_) {
      // The time the data will have at the control step's end: mj_step adds the timestep.
      control_step_end_time_ = data.time();
      for (int i = 0; i < steps; ++i) control_step_end_time_ += model.m()->opt.timestep;
      control_step_end_ = pose_at(model, control_step_end_time_);
      plan_inputs_ = inputs;
    }
  }
  if (!control_step_start_) return;
  const Posed& start = *control_step_start_;
  const double share = static_cast<double>(step) / steps;
  sim::set_human_pose(model, data,
                      control_step_end_ ? human::interpolate(start.pose, control_step_end_->pose, share) : start.pose);
  // The holds change at the physics step where the labels do, as drive's: where the ends hold
  // the same, nothing changes between them.
  if (step == 0) {
    hold_as_labelled(model, data, start.holds);
  } else if (control_step_end_ && !start.holds.same_as(control_step_end_->holds)) {
    if (const std::optional<Holds> holds = holds_at(model, data.time())) hold_as_labelled(model, data, *holds);
  }
}

ScriptDriver::PlanInputs ScriptDriver::plan_inputs() const {
  PlanInputs inputs;
  inputs.active = active_;
  for (size_t i = 0; i < motions_.size(); ++i) {
    inputs.signals += motions_[i].signals.size();
    switch (runtime_.acts[i].status) {
      case script::ActStatus::kWaiting: break;
      case script::ActStatus::kRunning: inputs.progress += 1; break;
      case script::ActStatus::kDone:
      case script::ActStatus::kSkipped: inputs.progress += 2; break;
    }
  }
  return inputs;
}

void ScriptDriver::hold_as_labelled(const model::Model& model, sim::Data& data, const Holds& holds) {
  // Hand holds follow the owning plan's labels (changes within one plan only).
  for (size_t h = 0; h < 2; ++h) {
    const std::string& holding = holds.holding(h);
    if (holding_plan_[h] != holds.owner[h]) {
      holding_plan_[h] = holds.owner[h];
      last_holding_[h] = holding;
      continue;
    }
    if (holding == last_holding_[h]) continue;
    last_holding_[h] = holding;
    if (!holding.empty()) {
      const int object = model.object_index(holding);
      if (object >= 0 && sim::held_object(data, kSides[h]) != object) grasp(model, data, kSides[h], object);
    } else if (sim::held_object(data, kSides[h])) {
      sim::release_by_human(model, data, kSides[h]);
    }
  }
}

void ScriptDriver::fill_world(const model::Model& model, const sim::Data& data) {
  const mjModel* m = model.m();
  const mjData* d = data.mj.get();
  world_.time = data.time();
  // Objects.
  std::vector<int> graph_of_model(model.objects.size(), -1);
  for (size_t i = 0; i < object_of_graph_.size(); ++i) {
    if (object_of_graph_[i] < 0) continue;  // a platform: fixed, set at reset
    const size_t o = static_cast<size_t>(object_of_graph_[i]);
    graph_of_model[o] = static_cast<int>(i);
    const model::ObjectInfo& info = model.objects[o];
    script::ObjectState& state = world_.objects[i];
    state.X_WO = object_centre_pose(model, data, o);
    const mjtNum* v = d->qvel + info.dof_adr;
    state.v_WO = core::Vec3(v[0], v[1], v[2]);
    state.lid_deg = info.lid_joint >= 0
                        ? std::abs(d->qpos[m->jnt_qposadr[info.lid_joint]]) / kDegToRad
                        : 0.0;
    state.left_finger_contact = state.right_finger_contact = false;
  }
  // Finger pads touching objects.
  for (const sim::Contact& c : sim::find_contacts(model, data)) {
    if (c.a.owner != model::GeomOwner::kRobotFinger || c.b.owner != model::GeomOwner::kObject) continue;
    if (c.b.index < 0 || static_cast<size_t>(c.b.index) >= graph_of_model.size()) continue;
    const int g = graph_of_model[static_cast<size_t>(c.b.index)];
    if (g < 0) continue;
    (c.a.index == 0 ? world_.objects[static_cast<size_t>(g)].left_finger_contact
                    : world_.objects[static_cast<size_t>(g)].right_finger_contact) = true;
  }
  // Robot tool-centre point and gripper.
  const size_t tcp = static_cast<size_t>(model.tcp_site);
  mjtNum quat[4];
  mju_mat2Quat(quat, d->site_xmat + 9 * tcp);
  world_.X_WT.rotation = core::quat_from_wxyz(quat).normalized();
  world_.X_WT.translation = core::Vec3(d->site_xpos[3 * tcp], d->site_xpos[3 * tcp + 1], d->site_xpos[3 * tcp + 2]);
  mjtNum velocity[6];
  mj_objectVelocity(m, d, mjOBJ_SITE, model.tcp_site, velocity, 0);
  world_.v_WT = core::Vec3(velocity[3], velocity[4], velocity[5]);
  world_.gripper_width = sim::gripper_width(model, data);
  world_.gripper_speed = d->qvel[model.finger_dof_adr[0]] + d->qvel[model.finger_dof_adr[1]];
  world_.home_distance = (world_.X_WT.translation - p_WT_home_).norm();
  // Hands.
  for (size_t h = 0; h < 2; ++h) {
    script::HandState& hand = world_.hands[h];
    hand.held_object = -1;
    if (!model.has_human) continue;
    hand.p_W = (data.X_WJ[static_cast<size_t>(kWrist[h])] * model.X_wrist_palm[h]).translation;
    const std::optional<int> held = sim::held_object(data, kSides[h]);
    if (held && *held >= 0 && static_cast<size_t>(*held) < graph_of_model.size()) {
      hand.held_object = graph_of_model[static_cast<size_t>(*held)];
    }
  }
}

void ScriptDriver::start_plan(const model::Model& model, const sim::Data& data, size_t act) {
  ActMotion& motion = motions_[act];
  motion.start = runtime_.acts[act].start;
  motion.phase = 0;
  const std::optional<script::Motion>& spec_motion = script_->spec->acts[act].value.motion;
  if (!model.has_human || !spec_motion) return;
  if (spec_motion->clip) {
    start_clip(model, data, act);
    return;
  }
  if (!spec_motion->primitive) return;
  const auto centre = [&](const std::string& name) {
    for (size_t i = 0; i < script_->graph.objects.size(); ++i) {
      if (script_->graph.objects[i] == name) return world_.objects[i].X_WO.translation;
    }
    throw core::InputError("acts." + script_->spec->acts[act].name + ".motion", "a scene object", name);
  };
  motion.knots = {};
  motion.plan.emplace(human::plan_motion(model.skeleton, data.human_pose,
                                         primitive_params(*script_->spec, act, centre)));
  for (size_t h = 0; h < 2; ++h) motion.moves[h] = moves_hand(*motion.plan, h);
  motion.moves_root = moves_root(*motion.plan);
  // Waiting phases the runtime does not hold open end at their nominal time.
  const script::CompiledAct& compiled = script_->graph.acts[act];
  for (const human::Segment& segment : motion.plan->segments()) {
    if (!segment.waits || segment.phase.empty()) continue;
    bool held_open = false;
    for (const script::CompiledPhase& phase : compiled.phases) {
      if (phase.name == segment.phase && phase.waits) held_open = true;
    }
    if (!held_open) motion.signals[segment.phase] = 0;
  }
}

void ScriptDriver::start_clip(const model::Model& model, const sim::Data& data, size_t act) {
  ActMotion& motion = motions_[act];
  const script::Motion& spec_motion = *script_->spec->acts[act].value.motion;
  human::RetargetOptions options;
  options.height = model.skeleton.height;
  human::Clip clip = human::read_clip(spec_motion.clip->value(), options);
  // Stretched to the act's duration, placed where the body stands, facing its way.
  for (const script::Entry<script::ValueTree>& p : spec_motion.params) {
    if (p.name == "duration" && clip.duration() > 0) clip = human::time_scale(clip, p.value.scalar.expr.number / clip.duration());
  }
  const core::Vec3& pelvis = data.human_pose.X_WP.translation;
  clip = human::place(clip, pelvis.x(), pelvis.y(), human::facing_yaw(data.human_pose));
  motion.moves = {true, true};
  motion.moves_root = false;
  for (const human::SkeletonPose& frame : clip.frames) {
    const core::Vec3 d = frame.X_WP.translation - clip.frames.front().X_WP.translation;
    if (std::hypot(d.x(), d.y()) > 0.01) motion.moves_root = true;
  }
  motion.clip.emplace(std::move(clip));
}

void ScriptDriver::update_signals(size_t act) {
  ActMotion& motion = motions_[act];
  const script::ActState& state = runtime_.acts[act];
  const std::vector<script::CompiledPhase>& phases = script_->graph.acts[act].phases;
  size_t reached = motion.phase;
  double at = world_.time;
  if (state.status == script::ActStatus::kRunning) {
    reached = state.phase;
    at = state.phase_start;
  } else if (state.status == script::ActStatus::kDone) {
    reached = phases.size();
    const int end = script_->graph.acts[act].end_event;
    if (end >= 0 && std::isfinite(runtime_.event_time[static_cast<size_t>(end)])) {
      at = runtime_.event_time[static_cast<size_t>(end)];
    }
  }
  for (size_t k = motion.phase; k < reached && k < phases.size(); ++k) {
    if (phases[k].waits && !phases[k].name.empty() && motion.signals.count(phases[k].name) == 0) {
      motion.signals[phases[k].name] = at - motion.start;
    }
  }
  motion.phase = std::max(motion.phase, reached);
}

void ScriptDriver::observe(const model::Model& model, const sim::Data& data,
                           std::vector<uint8_t>& predicates, std::vector<Event>& events) {
  fill_world(model, data);
  script::step(script_->graph, runtime_, world_);
  // Plans for human acts that started; the latest started act moves the body.
  for (size_t i = 0; i < script_->graph.acts.size(); ++i) {
    if (!script_->graph.acts[i].human) continue;
    const script::ActStatus status = runtime_.acts[i].status;
    if (status == script::ActStatus::kWaiting || status == script::ActStatus::kSkipped) continue;
    if (!motions_[i].started) {
      motions_[i].started = true;
      start_plan(model, data, i);
      if (active_ < 0 || motions_[i].start >= motions_[static_cast<size_t>(active_)].start) {
        active_ = static_cast<int>(i);
      }
    }
    if (motions_[i].plan) update_signals(i);
  }
  // New runtime events.
  for (; events_seen_ < runtime_.events.size(); ++events_seen_) {
    const script::Event& e = runtime_.events[events_seen_];
    if (e.id < 0 || static_cast<size_t>(e.id) >= script_->event_info.size()) continue;
    const EventInfo& info = script_->event_info[static_cast<size_t>(e.id)];
    events.push_back(Event{e.time, info.kind, info.actor, info.name, info.detail});
    if (!info.cue_kind.empty()) events.push_back(Event{e.time, EventKind::kCue, Actor::kHuman, info.name, info.cue_kind});
  }
  bool success = !script_->graph.success.empty();
  for (const int p : script_->graph.success) success = success && runtime_.value[static_cast<size_t>(p)] != 0;
  predicates.assign(script_->predicate_names.size(), 0);
  predicates[0] = success ? 1 : 0;
  if (script_->predicate_names.size() == 3) {
    // intent: once a contradicting act has started, the success predicates (they state the
    // latest intent); before, the instruction is the latest intent: the contradicted act's
    // goal. contradicted: the goal of a robot act that a started human act contradicts holds.
    bool contradicted = false;
    bool given = false;
    bool instructed = true;
    for (size_t i = 0; i < script_->graph.acts.size(); ++i) {
      const script::CompiledAct& act = script_->graph.acts[i];
      if (!act.human || act.contradicts < 0) continue;
      const int goal = script_->graph.acts[static_cast<size_t>(act.contradicts)].goal;
      const bool holds = goal >= 0 && runtime_.value[static_cast<size_t>(goal)] != 0;
      const script::ActStatus status = runtime_.acts[i].status;
      if (status != script::ActStatus::kRunning && status != script::ActStatus::kDone) {
        instructed = instructed && holds;
        continue;
      }
      given = true;
      if (holds) contradicted = true;
    }
    predicates[1] = given ? predicates[0] : (instructed ? 1 : 0);
    predicates[2] = contradicted ? 1 : 0;
  }
}

}  // namespace hribench::eval
