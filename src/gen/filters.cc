#include "gen/filters.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <set>

#include <fmt/format.h>

#include "core/errors.h"
#include "eval/metrics.h"
#include "eval/runner.h"
#include "eval/script_contract.h"
#include "eval/script_driver.h"
#include "eval/task_episode.h"
#include "policy/registry.h"
#include "script/predicate.h"
#include "script/runtime.h"
#include "sim/control.h"
#include "sim/distance.h"

namespace hribench::gen {
namespace {

using core::Vec3;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The centre of an object's bounding box at its start pose (world).
Vec3 object_centre(const model::ObjectInfo& object) {
  return object.X_W_start * Vec3(0, 0, object.half_extents.z());
}

// Object index in the model of a graph object index (-1 if absent).
int model_object(const model::Model& model, const script::ActGraph& graph, int graph_object) {
  if (graph_object < 0 || static_cast<size_t>(graph_object) >= graph.objects.size()) return -1;
  return model.object_index(graph.objects[static_cast<size_t>(graph_object)]);
}

// "ACT.PHASE" -> "PHASE" ("" when there is no dot).
std::string phase_of(const std::string& event) {
  const size_t dot = event.find('.');
  return dot == std::string::npos ? std::string() : event.substr(dot + 1);
}

std::optional<human::Side> side_of(const std::string& text) {
  if (text.rfind("left.", 0) == 0) return human::Side::kLeft;
  if (text.rfind("right.", 0) == 0) return human::Side::kRight;
  return std::nullopt;
}

// Places a robot goal names (not under `not`): objects to grasp (grasped, held_for, the
// first object of in/on, a lid to open) and places to reach above (the container or surface of
// in/on, an object to come near). Graph object indices.
struct RobotTargets {
  std::set<int> grasp;
  std::set<int> above;
};
void robot_targets(const script::Predicate& p, RobotTargets& out) {
  using script::Arg;
  using script::Atom;
  const auto object = [&](size_t i, std::set<int>& set) {
    if (i < p.args.size() && p.args[i].kind == Arg::Kind::kObject) set.insert(p.args[i].index);
  };
  const bool robot = !p.args.empty() && p.args[0].kind == Arg::Kind::kRobot;
  switch (p.atom) {
    case Atom::kNot: return;
    case Atom::kAnd:
    case Atom::kOr:
    case Atom::kEver:
      for (const script::Predicate& c : p.children) robot_targets(c, out);
      return;
    case Atom::kGrasped:
    case Atom::kHeldFor:
      if (robot) object(1, out.grasp);
      return;
    case Atom::kIn:
    case Atom::kOn:
      object(0, out.grasp);
      object(1, out.above);
      return;
    case Atom::kNear:
      if (robot) object(1, out.above);
      return;
    case Atom::kOpen: object(0, out.grasp); return;
    default: return;
  }
}

// Every object a predicate names (negated or not). Graph indices.
void named_objects(const script::Predicate& p, std::set<int>& out) {
  for (const script::Arg& a : p.args) {
    if (a.kind == script::Arg::Kind::kObject) out.insert(a.index);
  }
  for (const script::Predicate& c : p.children) named_objects(c, out);
}

// A top-down TCP pose at p_W, yawed by `yaw` about world z: the TCP z axis points down.
core::Pose top_down(const Vec3& p_W, double yaw) {
  core::Pose X;
  X.rotation = core::axis_angle(Vec3::UnitZ(), yaw) * core::axis_angle(Vec3::UnitX(), core::kPi);
  X.translation = p_W;
  return X;
}

// Differential IK from home toward X_WT, iterated until it settles. True when the TCP reaches
// it within tolerance with every joint kReachJointMargin inside its limits; `why` says what
// failed otherwise.
bool reach(const model::Model& model, sim::Data& data, const core::Pose& X_WT, std::string& why) {
  sim::reset(model, data);
  sim::IkResult ik;
  for (int i = 0; i < 60; ++i) {
    ik = sim::set_tcp_target(model, data, X_WT);
    for (size_t j = 0; j < ik.q_target.size(); ++j) {
      data.mj->qpos[model.arm_qpos_adr[j]] = ik.q_target[j];
    }
    if (ik.position_error < 1e-4 && ik.rotation_error < 1e-3) break;
  }
  if (ik.position_error > kReachPositionTolerance || ik.rotation_error > kReachRotationTolerance) {
    why = fmt::format("IK misses by {:.3f} m, {:.3f} rad", ik.position_error, ik.rotation_error);
    return false;
  }
  for (size_t j = 0; j < ik.q_target.size(); ++j) {
    const double q = ik.q_target[j];
    const model::ArmJoint& joint = model.robot.joints[j];
    if (q < joint.q_min + kReachJointMargin || q > joint.q_max - kReachJointMargin) {
      why = fmt::format("joint {} at {:.3f} rad is within {} rad of its limit", j + 1, q,
                        kReachJointMargin);
      return false;
    }
  }
  return true;
}

// A human capsule in world, from the posed joint frames.
sim::Capsule world_capsule(const model::Model& model, const sim::Data& data, size_t i) {
  const human::BodyCapsule& c = model.human_capsules[i];
  const core::Pose& X_WJ = data.X_WJ[static_cast<size_t>(c.joint)];
  return sim::Capsule{sim::Segment{X_WJ * c.from, X_WJ * c.to}, c.radius};
}

bool is_hand(const human::BodyCapsule& c) {
  return c.joint == human::wrist(human::Side::kLeft) || c.joint == human::wrist(human::Side::kRight);
}

// The root body of a geom's body (objects are free bodies under the world; a lid is a child).
int root_body(const mjModel& m, int geom) {
  return m.body_rootid[m.geom_bodyid[geom]];
}

// agentview as a policy sees it: the camera's pose, and its focal length in pixels of a
// kCueImageSize square image.
struct AgentView {
  Vec3 p_WC;
  core::Mat3 R_WC;    // camera frame: looks along -z, y up, x right
  double tan_half;    // tan of half the field of view
  double focal_px;

  AgentView(const model::Model& model, const sim::Data& data) {
    const int cam = model.agentview_camera;
    const mjData& d = *data.mj;
    p_WC = Vec3(d.cam_xpos[3 * cam], d.cam_xpos[3 * cam + 1], d.cam_xpos[3 * cam + 2]);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) R_WC(r, c) = d.cam_xmat[9 * cam + 3 * r + c];
    }
    tan_half = std::tan(0.5 * model.m()->cam_fovy[cam] * core::kPi / 180.0);
    focal_px = 0.5 * kCueImageSize / tan_half;
  }
  Vec3 in_camera(const Vec3& p_W) const { return R_WC.transpose() * (p_W - p_WC); }
  // (u right, v down) in pixels from the image's top left corner, and the depth (m).
  Vec3 pixel(const Vec3& p_W) const {
    const Vec3 p_C = in_camera(p_W);
    const double depth = -p_C.z();
    return Vec3(0.5 * kCueImageSize + focal_px * p_C.x() / depth, 0.5 * kCueImageSize - focal_px * p_C.y() / depth,
                depth);
  }
};

// A ball in world (a point when radius is 0): what a body shows itself with.
struct Ball {
  Vec3 p_W;
  double radius = 0;
};
// Pixels across that `balls` appear in agentview at kCueImageSize: the smaller side of the
// rectangle that holds their projections (each ball a disc of radius focal * r / depth).
double pixels_across(const AgentView& view, const std::vector<Ball>& balls) {
  double u0 = std::numeric_limits<double>::infinity(), v0 = u0, u1 = -u0, v1 = -u0;
  for (const Ball& b : balls) {
    const Vec3 px = view.pixel(b.p_W);
    const double r = view.focal_px * b.radius / px.z();
    u0 = std::min(u0, px.x() - r);
    u1 = std::max(u1, px.x() + r);
    v0 = std::min(v0, px.y() - r);
    v1 = std::max(v1, px.y() + r);
  }
  return balls.empty() ? 0 : std::min(u1 - u0, v1 - v0);
}

// The corners of an object's bounding box at its current pose.
std::vector<Ball> box_corners(const sim::Data& data, const model::ObjectInfo& object) {
  const mjtNum* xpos = data.mj->xpos + 3 * object.body;
  const core::Pose X_WO{core::quat_from_wxyz(data.mj->xquat + 4 * object.body), Vec3(xpos[0], xpos[1], xpos[2])};
  const Vec3& h = object.half_extents;
  std::vector<Ball> corners;
  for (const double x : {-h.x(), h.x()}) {
    for (const double y : {-h.y(), h.y()}) {
      for (const double z : {0.0, 2 * h.z()}) corners.push_back(Ball{X_WO * Vec3(x, y, z), 0});
    }
  }
  return corners;
}

// Is p_W inside the agentview image (square, kImageMargin of the half field of view) and not
// hidden behind another geom? `accepts(geom)` says which geoms belong to the target itself.
template <typename Accepts>
bool visible(const model::Model& model, const sim::Data& data, const Vec3& p_W, Accepts accepts,
             std::string& why) {
  const mjModel& m = *model.m();
  const mjData& d = *data.mj;
  const AgentView view(model, data);
  const Vec3 p_C = view.in_camera(p_W);
  const double depth = -p_C.z();
  const double half = view.tan_half * kImageMargin;
  if (depth <= 0.05 || std::abs(p_C.x()) > half * depth || std::abs(p_C.y()) > half * depth) {
    why = "outside the image";
    return false;
  }
  const Vec3 ray = p_W - view.p_WC;
  mjtNum pnt[3] = {view.p_WC.x(), view.p_WC.y(), view.p_WC.z()};
  mjtNum vec[3] = {ray.x(), ray.y(), ray.z()};
  int geom = -1;
  const mjtNum hit = mj_ray(&m, &d, pnt, vec, nullptr, 1, -1, &geom);
  if (geom < 0 || hit >= 0.999 || accepts(geom)) return true;
  why = fmt::format("hidden behind '{}'", mj_id2name(&m, mjOBJ_GEOM, geom) != nullptr
                                               ? mj_id2name(&m, mjOBJ_GEOM, geom)
                                               : "a geom");
  return false;
}

}  // namespace

std::string_view to_string(Filter filter) {
  switch (filter) {
    case Filter::kOrdering: return "ordering";
    case Filter::kScene: return "scene";
    case Filter::kSuccess: return "success";
    case Filter::kReachable: return "reachable";
    case Filter::kPenetration: return "penetration";
    case Filter::kLabels: return "labels";
    case Filter::kVisibility: return "visibility";
    case Filter::kExecutable: return "executable";
    case Filter::kAtRest: return "at_rest";
  }
  return "?";
}

std::optional<Filter> filter_from_name(std::string_view name) {
  for (const Filter f : kFilters) {
    if (to_string(f) == name) return f;
  }
  return std::nullopt;
}

CandidateScene make_candidate_scene(const script::EpisodeSpec& spec) {
  CandidateScene scene;
  scene.spec = &spec;
  scene.model = model::build(eval::scene_spec_from_episode(spec));
  scene.data = sim::make_data(scene.model);
  const model::Model& model = scene.model;
  if (!model.has_human) return scene;
  const auto centre = [&](const std::string& name) {
    const int i = model.object_index(name);
    if (i < 0) throw core::InputError("motion", "a scene object", "'" + name + "'");
    return model.objects[static_cast<size_t>(i)].X_W_start.translation;
  };
  // Acts follow each other in spec order, each from where the previous one ended; an act
  // that fails the episode (giving up) is an alternative ending and moves nobody on.
  human::SkeletonPose pose = model.human_start;
  for (size_t a = 0; a < spec.acts.size(); ++a) {
    const script::Act& act = spec.acts[a].value;
    if (act.actor != "human" || !act.motion || !act.motion->primitive) continue;
    PlannedAct planned;
    planned.act = a;
    planned.params = eval::primitive_params(spec, a, centre);
    const human::MotionPlan plan = human::plan_motion(model.skeleton, pose, planned.params);
    planned.active_hand = plan.active_hand();
    planned.clip = plan.to_clip(kPlanFps);
    if (!act.fails && !planned.clip.clip.frames.empty()) pose = planned.clip.clip.frames.back();
    scene.plans.push_back(std::move(planned));
  }
  return scene;
}

FilterOutcome check_ordering(const script::EpisodeSpec& spec) {
  script::ActGraph graph;
  try {
    graph = script::compile(spec);
  } catch (const std::exception& e) {
    return FilterOutcome::Fail(std::string("the act graph does not compile: ") + e.what());
  }
  const double horizon = spec.horizon;
  std::vector<double> t(graph.event_names.size(), kNaN);
  const auto known = [&](int event) { return event >= 0 && std::isfinite(t[static_cast<size_t>(event)]); };
  const auto at = [&](int event) { return t[static_cast<size_t>(event)]; };
  const auto set = [&](int event, double time) {
    if (event >= 0) t[static_cast<size_t>(event)] = time;
  };
  // Nominal times of the human acts scheduled by time (onset, after + delay), waiting phases at
  // their minimum; acts started by a predicate (`when`) or after an unknown event stay unknown.
  std::vector<char> scheduled(graph.acts.size(), 0);
  for (size_t pass = 0; pass <= graph.acts.size(); ++pass) {
    for (size_t i = 0; i < graph.acts.size(); ++i) {
      const script::CompiledAct& act = graph.acts[i];
      if (!act.human || scheduled[i] || act.when >= 0) continue;
      if (act.after_event >= 0 && !known(act.after_event)) continue;
      double time = act.onset;
      if (act.after_event >= 0) time = std::max(time, at(act.after_event) + act.delay);
      set(act.start_event, time);
      for (const script::CompiledPhase& phase : act.phases) {
        if (!std::isfinite(phase.duration) || phase.duration < 0) {
          return FilterOutcome::Fail(fmt::format("{}.{} lasts {} s", act.name, phase.name, phase.duration));
        }
        set(phase.event, time);
        time += phase.duration;
      }
      set(act.end_event, time);
      scheduled[i] = 1;
      if (!act.fails && time > horizon) {
        return FilterOutcome::Fail(
            fmt::format("{} ends at {:.2f} s, after the horizon ({} s)", act.name, time, horizon));
      }
    }
  }
  for (const script::CompiledAct& act : graph.acts) {
    if (act.human && act.cue && known(act.cue->event) && at(act.cue->event) + act.cue->window > horizon) {
      return FilterOutcome::Fail(fmt::format("the cue {} at {:.2f} s + window {} s ends after the horizon ({} s)",
                                             graph.event_names[static_cast<size_t>(act.cue->event)],
                                             at(act.cue->event), act.cue->window, horizon));
    }
    if (act.human) continue;
    const script::RobotConstraints& c = act.constraints;
    if (known(c.after) && c.within >= 0 && at(c.after) + c.within > horizon) {
      return FilterOutcome::Fail(fmt::format("{} must start by {:.2f} s, after the horizon ({} s)",
                                             act.name, at(c.after) + c.within, horizon));
    }
    if (known(c.after) && known(c.before) && at(c.after) >= at(c.before)) {
      return FilterOutcome::Fail(fmt::format("{} must start after {:.2f} s and end before {:.2f} s",
                                             act.name, at(c.after), at(c.before)));
    }
    if (known(c.sync_with)) {
      const double target = at(c.sync_with) + c.sync_offset;
      if (target < 0 || target > horizon) {
        return FilterOutcome::Fail(fmt::format("{} is synchronised to start at {:.2f} s, outside [0, {}] s",
                                               act.name, target, horizon));
      }
    }
    if (known(c.still_from) && known(c.still_to) && at(c.still_from) > at(c.still_to)) {
      return FilterOutcome::Fail(fmt::format("{} must stay still from {:.2f} s to {:.2f} s", act.name,
                                             at(c.still_from), at(c.still_to)));
    }
  }
  return FilterOutcome::Pass();
}

FilterOutcome check_success(CandidateScene& scene) {
  const script::EpisodeSpec& spec = *scene.spec;
  if (spec.success.empty()) return FilterOutcome::Fail("no success predicates");
  try {
    eval::ScriptDriver driver(spec);
    if (driver.graph().success.empty()) return FilterOutcome::Fail("no success predicates");
    sim::reset(scene.model, scene.data);
    driver.reset(scene.model, scene.data);
    std::vector<uint8_t> predicates;
    std::vector<eval::Event> events;
    driver.observe(scene.model, scene.data, predicates, events);
  } catch (const std::exception& e) {
    return FilterOutcome::Fail(std::string("success is not evaluable: ") + e.what());
  }
  return FilterOutcome::Pass();
}

FilterOutcome check_reachable(CandidateScene& scene) {
  const model::Model& model = scene.model;
  const script::ActGraph graph = script::compile(*scene.spec);
  RobotTargets targets;
  for (const script::CompiledAct& act : graph.acts) {
    if (!act.human && act.goal >= 0) robot_targets(graph.predicates[static_cast<size_t>(act.goal)].root, targets);
  }
  // Grasp at the centre (at most 5 cm above the bottom); reach kPlaceClearance above the top;
  // either yaw of the footprint's axes will do.
  const auto check = [&](int g, bool above) -> std::optional<std::string> {
    const int o = model_object(model, graph, g);
    if (o < 0) return std::nullopt;
    const model::ObjectInfo& object = model.objects[static_cast<size_t>(o)];
    if (object.held_by) return std::nullopt;  // handed over: the target is the person's hand
    const double yaw = 2 * std::atan2(object.X_W_start.rotation.z(), object.X_W_start.rotation.w());
    const double hz = object.half_extents.z();
    const Vec3 p = object.X_W_start.translation + Vec3(0, 0, above ? 2 * hz + kPlaceClearance : std::min(hz, 0.05));
    std::string why, why_turned;
    if (reach(model, scene.data, top_down(p, yaw), why) ||
        reach(model, scene.data, top_down(p, yaw + 0.5 * core::kPi), why_turned)) {
      return std::nullopt;
    }
    return fmt::format("{} ({}) at ({:.2f}, {:.2f}, {:.2f}) is out of reach: {}", object.name,
                       above ? "above" : "grasp", p.x(), p.y(), p.z(), why);
  };
  for (const int g : targets.grasp) {
    if (const auto why = check(g, false)) return FilterOutcome::Fail(*why);
  }
  for (const int g : targets.above) {
    if (const auto why = check(g, true)) return FilterOutcome::Fail(*why);
  }
  sim::reset(model, scene.data);
  return FilterOutcome::Pass();
}

FilterOutcome check_penetration(CandidateScene& scene) {
  const model::Model& model = scene.model;
  if (!model.has_human) return FilterOutcome::Pass();
  // Objects the person starts with or carries move with the hand: not checked.
  std::set<std::string> carried;
  for (const model::ObjectInfo& o : model.objects) {
    if (o.held_by) carried.insert(o.name);
  }
  for (const PlannedAct& plan : scene.plans) {
    for (const human::FrameLabel& label : plan.clip.labels) {
      for (const human::HandLabel& hand : label.hands) {
        if (!hand.holding.empty()) carried.insert(hand.holding);
      }
    }
  }
  const double slab = 0.05;
  const sim::Box table{Vec3(0.5 * (model::kTableXMin + model::kTableXMax), 0, model::kTableTopZ - 0.5 * slab),
                       core::Mat3::Identity(),
                       Vec3(0.5 * (model::kTableXMax - model::kTableXMin), 0.5 * model::kTableWidth, 0.5 * slab)};
  std::vector<std::pair<std::string, sim::Box>> boxes = {{"the table", table}};
  for (const model::ObjectInfo& o : model.objects) {
    if (carried.count(o.name) != 0) continue;
    core::Pose X_W_centre = o.X_W_start;
    X_W_centre.translation = object_centre(o);
    boxes.emplace_back(o.name, sim::Box::FromPose(X_W_centre, o.half_extents));
  }
  sim::Data& data = scene.data;
  for (const PlannedAct& plan : scene.plans) {
    const human::Clip& clip = plan.clip.clip;
    for (size_t f = 0; f < clip.frames.size(); ++f) {
      sim::set_human_pose(model, data, clip.frames[f]);
      sim::pose_human(model, data);
      for (size_t i = 0; i < model.human_capsules.size(); ++i) {
        const sim::Capsule capsule = world_capsule(model, data, i);
        for (size_t b = 0; b < boxes.size(); ++b) {
          // Hands never collide with objects in the model. Against the table: forearm bones
          // must stay out; hands have kHandTableTolerance.
          const human::BodyCapsule& c = model.human_capsules[i];
          const bool hand = is_hand(c);
          if (b > 0 && hand) continue;
          double tolerance = kPenetrationTolerance;
          if (b == 0 && hand) tolerance = kHandTableTolerance;
          if (b == 0 && c.region == human::BodyRegion::kForearm) tolerance = std::max(tolerance, c.radius);
          const double d = sim::closest_points(capsule, boxes[b].second).distance;
          if (d < -tolerance) {
            return FilterOutcome::Fail(fmt::format(
                "{}'s {} enters {} by {:.3f} m at {:.1f} s", scene.spec->acts[plan.act].name,
                model.human_capsules[i].name, boxes[b].first, -d, static_cast<double>(f) / kPlanFps));
          }
        }
      }
    }
  }
  sim::reset(model, data);
  return FilterOutcome::Pass();
}

FilterOutcome check_labels(const CandidateScene& scene) {
  const script::EpisodeSpec& spec = *scene.spec;
  const model::Model& model = scene.model;
  for (const PlannedAct& plan : scene.plans) {
    const script::Entry<script::Act>& entry = spec.acts[plan.act];
    if (!entry.value.label) continue;
    const script::Label& label = *entry.value.label;
    const std::string phase = phase_of(label.during);
    const human::Clip& clip = plan.clip.clip;
    human::CheckResult result;
    if (!label.ray.empty() && label.through) {
      const std::optional<human::Side> side = side_of(label.ray.back().value());
      const int target = model.object_index(label.through->value());
      if (!side || target < 0) return FilterOutcome::Fail(entry.name + ".label names no hand or object");
      const Vec3 p_target = object_centre(model.objects[static_cast<size_t>(target)]);
      result = human::check_pointing(clip, *side, p_target, kCueRegionRadius, phase);
      // The ray must single out the target: nearer to it than to any other object.
      for (size_t f = 0; result.ok && f < clip.frames.size(); ++f) {
        if (f >= plan.clip.labels.size() || plan.clip.labels[f].phase != phase) continue;
        const double to_target = human::pointing_ray_distance(clip.skeleton, clip.frames[f], *side, p_target);
        for (size_t o = 0; o < model.objects.size(); ++o) {
          if (static_cast<int>(o) == target) continue;
          const double to_other = human::pointing_ray_distance(clip.skeleton, clip.frames[f], *side,
                                                               object_centre(model.objects[o]));
          if (to_other < to_target) {
            result.ok = false;
            result.message = fmt::format("{}: the ray passes nearer to {} than to {}", phase,
                                         model.objects[o].name, model.objects[static_cast<size_t>(target)].name);
            break;
          }
        }
      }
    } else if (label.joint) {
      const std::string& joint = label.joint->value();
      const std::optional<human::Side> side = side_of(joint);
      const std::optional<human::HandPoint> point = human::hand_point_from_name(phase_of(joint));
      if (!side || !point) return FilterOutcome::Fail(entry.name + ".label names no hand point");
      if (label.in) {
        const std::string zone_name = phase_of(*label.in);
        const auto zone = plan.params.zones.find(zone_name);
        if (zone == plan.params.zones.end()) {
          return FilterOutcome::Fail(entry.name + ".label: the act has no zone '" + zone_name + "'");
        }
        result = human::check_stable_in_zone(clip, *side, *point, zone->second, phase, kLabelStillSpeed);
      } else if (label.crosses) {
        result = human::check_enters_box(clip, *side, *point, kWorkspace, phase);
      }
    }
    if (!result.ok) return FilterOutcome::Fail(entry.name + ".label: " + result.message);
  }
  return FilterOutcome::Pass();
}

FilterOutcome check_visibility(CandidateScene& scene) {
  const script::EpisodeSpec& spec = *scene.spec;
  const model::Model& model = scene.model;
  const mjModel& m = *model.m();
  sim::Data& data = scene.data;
  sim::reset(model, data);
  // Key objects: every object a robot goal or a success predicate names.
  const script::ActGraph graph = script::compile(spec);
  std::set<int> key;
  for (const script::CompiledAct& act : graph.acts) {
    if (!act.human && act.goal >= 0) named_objects(graph.predicates[static_cast<size_t>(act.goal)].root, key);
  }
  for (const int p : graph.success) named_objects(graph.predicates[static_cast<size_t>(p)].root, key);
  for (const int g : key) {
    const int o = model_object(model, graph, g);
    if (o < 0) continue;
    const model::ObjectInfo& object = model.objects[static_cast<size_t>(o)];
    // An object that starts inside a container is seen through its container.
    const auto in_container = std::find_if(spec.scene.objects.begin(), spec.scene.objects.end(),
                                           [&](const auto& e) { return e.name == object.name && e.value.in; });
    if (in_container != spec.scene.objects.end()) continue;
    const mjtNum* xpos = data.mj->xpos + 3 * object.body;
    const core::Quat q = core::quat_from_wxyz(data.mj->xquat + 4 * object.body);
    const Vec3 p_W = Vec3(xpos[0], xpos[1], xpos[2]) + q * Vec3(0, 0, object.half_extents.z());
    const auto own = [&](int geom) { return root_body(m, geom) == object.body; };
    std::string why, why_top;
    if (!visible(model, data, p_W, own, why) &&
        !visible(model, data, p_W + q * Vec3(0, 0, object.half_extents.z()), own, why_top)) {
      return FilterOutcome::Fail(fmt::format("{} is not visible in agentview: {}", object.name, why));
    }
    const double across = pixels_across(AgentView(model, data), box_corners(data, object));
    if (across < kMinKeyObjectPixels) {
      return FilterOutcome::Fail(fmt::format("{} is {:.1f} px across in agentview at {} px, under {} px",
                                             object.name, across, kCueImageSize, kMinKeyObjectPixels));
    }
  }
  // A pointed target stands apart from every other object in the image.
  const AgentView view(model, data);
  for (const PlannedAct& plan : scene.plans) {
    const script::Act& act = spec.acts[plan.act].value;
    if (!act.label || act.label->ray.empty() || !act.label->through) continue;
    const int target = model.object_index(act.label->through->value());
    if (target < 0) continue;  // the labels filter names it
    const Vec3 p_target = view.pixel(object_centre(model.objects[static_cast<size_t>(target)]));
    for (size_t o = 0; o < model.objects.size(); ++o) {
      if (static_cast<int>(o) == target) continue;
      const Vec3 p_other = view.pixel(object_centre(model.objects[o]));
      const double apart = std::hypot(p_other.x() - p_target.x(), p_other.y() - p_target.y());
      if (apart < kMinPointedSeparationPixels) {
        return FilterOutcome::Fail(fmt::format(
            "{}'s pointed target {} is {:.1f} px from {} in agentview at {} px, under {} px",
            spec.acts[plan.act].name, model.objects[static_cast<size_t>(target)].name, apart,
            model.objects[o].name, kCueImageSize, kMinPointedSeparationPixels));
      }
    }
  }
  // The cue hand in the middle of each cue's phase.
  for (const PlannedAct& plan : scene.plans) {
    const script::Act& act = spec.acts[plan.act].value;
    if (!act.cue || !plan.active_hand) continue;
    const std::string phase = phase_of(act.cue->at);
    const human::Clip& clip = plan.clip.clip;
    size_t first = clip.frames.size(), last = 0;
    for (size_t f = 0; f < plan.clip.labels.size() && f < clip.frames.size(); ++f) {
      if (plan.clip.labels[f].phase == phase || (phase == "start" && f == 0) ||
          (phase == "end" && f + 1 == clip.frames.size())) {
        first = std::min(first, f);
        last = f;
      }
    }
    if (first >= clip.frames.size()) continue;  // a cue at an event the motion does not show
    const size_t frame = (first + last) / 2;
    const human::SkeletonPose& pose = clip.frames[frame];
    sim::set_human_pose(model, data, pose);
    sim::forward(model, data);
    const human::Side side = *plan.active_hand;
    // What the hand shows itself with: either hand, and what the hands hold.
    std::set<int> held;
    for (const human::HandLabel& hand : plan.clip.labels[frame].hands) {
      if (!hand.holding.empty() && model.object_index(hand.holding) >= 0) {
        held.insert(model.objects[static_cast<size_t>(model.object_index(hand.holding))].body);
      }
    }
    const auto own = [&](int geom) {
      const model::GeomTag& tag = model.geom_tags[static_cast<size_t>(geom)];
      return (tag.is_human() && tag.region == human::BodyRegion::kHand) || held.count(root_body(m, geom)) != 0;
    };
    // Seen when its palm, wrist or index fingertip is.
    std::string why;
    bool seen = false;
    for (const human::HandPoint point : {human::HandPoint::kPalm, human::HandPoint::kWrist, human::HandPoint::kIndexTip}) {
      std::string why_point;
      seen = seen || visible(model, data, human::hand_point(model.skeleton, pose, side, point), own, why_point);
      if (why.empty()) why = why_point;
    }
    if (!seen) {
      sim::reset(model, data);
      return FilterOutcome::Fail(fmt::format("the cue hand of {} ({}) is not visible in agentview: {}",
                                             spec.acts[plan.act].name, act.cue->at, why));
    }
    // Its capsules (palm and fingers), as large as the cue needs.
    const std::string_view prefix = side == human::Side::kLeft ? "left_" : "right_";
    std::vector<Ball> hand;
    for (size_t i = 0; i < model.human_capsules.size(); ++i) {
      const human::BodyCapsule& c = model.human_capsules[i];
      if (c.region != human::BodyRegion::kHand || c.name.substr(0, prefix.size()) != prefix) continue;
      const sim::Capsule capsule = world_capsule(model, data, i);
      hand.push_back(Ball{capsule.axis.p0_W, capsule.radius});
      hand.push_back(Ball{capsule.axis.p1_W, capsule.radius});
    }
    const double across = pixels_across(AgentView(model, data), hand);
    if (across < kMinCueHandPixels) {
      sim::reset(model, data);
      return FilterOutcome::Fail(fmt::format("the cue hand of {} ({}) is {:.1f} px across in agentview at {} px, under {} px",
                                             spec.acts[plan.act].name, act.cue->at, across, kCueImageSize,
                                             kMinCueHandPixels));
    }
  }
  sim::reset(model, data);
  return FilterOutcome::Pass();
}

namespace {

// One full episode of the policy `policy_ref` on the spec, as the rollout filters run it.
eval::ScoredEpisode roll_out(const script::EpisodeSpec& spec, const std::string& policy_ref,
                             const eval::RunOptions& options) {
  std::unique_ptr<policy::Policy> policy = policy::make_policy(policy_ref);
  const eval::EpisodeSetup setup{spec.task, spec.role, "", spec.seed, spec.instruction, policy_ref};
  return eval::run_task_episode(spec, *policy, setup, options);
}

// A rollout filter's rejection of an episode that did not end ok.
FilterOutcome ended_badly(const eval::EpisodeLog& log, const std::string& policy_ref) {
  return FilterOutcome::Fail(fmt::format("{} episode ended {}: {}", policy_ref, core::to_string(log.status),
                                         log.status_reason));
}

}  // namespace

FilterOutcome check_executable(const script::EpisodeSpec& spec, const std::string& policy_ref) {
  if (policy_ref == "none") return FilterOutcome::Pass();
  const eval::ScoredEpisode scored = roll_out(spec, policy_ref, eval::RunOptions{});
  const eval::EpisodeLog& log = scored.log;
  if (log.status != core::EpisodeStatus::kOk) return ended_badly(log, policy_ref);
  const eval::EpisodeMetrics& metrics = scored.metrics;
  if (!metrics.success) {
    return FilterOutcome::Fail(fmt::format(
        "{} does not succeed ({})", policy_ref,
        metrics.primary_label ? eval::to_string(*metrics.primary_label) : std::string_view("no label")));
  }
  return FilterOutcome::Pass();
}

FilterOutcome check_at_rest(const script::EpisodeSpec& spec) {
  const std::string policy_ref(kAtRestPolicy);
  // The whole horizon: a stand-down episode that noop "succeeds" still shows the person's acts.
  eval::RunOptions options;
  options.stop_on_success = false;
  const eval::EpisodeLog log = roll_out(spec, policy_ref, options).log;
  if (log.status != core::EpisodeStatus::kOk) return ended_badly(log, policy_ref);
  const eval::StepRecord* first_step = nullptr;
  const eval::Contact* first = nullptr;
  double peak = 0;
  for (const eval::StepRecord& step : log.steps) {
    for (const eval::Contact& c : step.contacts) {
      if (c.other_kind != eval::ContactOther::kHuman) continue;
      if (first == nullptr) {
        first_step = &step;
        first = &c;
      }
      peak = std::max(peak, c.normal_force);
    }
  }
  if (first == nullptr) return FilterOutcome::Pass();
  // The human phase under way: the last one that began by then.
  std::string during = "before the person's first act";
  for (const eval::Event& e : log.events) {
    if (e.time > first_step->time) break;
    if (e.actor == eval::Actor::kHuman && e.kind == eval::EventKind::kPhase) during = "during " + e.name;
  }
  return FilterOutcome::Fail(fmt::format(
      "the person's {} ({}) touches the robot at rest ({}) at {:.2f} s {}, {:.1f} N (peak {:.1f} N)", first->other,
      first->region ? human::to_string(*first->region) : std::string_view("?"), first->robot_part,
      first_step->time, during, first->normal_force, peak));
}

Verdict validate_candidate(const script::EpisodeSpec& spec, const FilterOptions& options) {
  const auto fail = [](Filter f, const FilterOutcome& o) { return Verdict{f, o.reason}; };
  FilterOutcome o = check_ordering(spec);
  if (!o.ok) return fail(Filter::kOrdering, o);
  std::optional<CandidateScene> scene;
  try {
    scene.emplace(make_candidate_scene(spec));
  } catch (const std::exception& e) {
    return Verdict{Filter::kScene, e.what()};
  }
  if (o = check_success(*scene); !o.ok) return fail(Filter::kSuccess, o);
  if (o = check_reachable(*scene); !o.ok) return fail(Filter::kReachable, o);
  if (o = check_penetration(*scene); !o.ok) return fail(Filter::kPenetration, o);
  if (o = check_labels(*scene); !o.ok) return fail(Filter::kLabels, o);
  if (o = check_visibility(*scene); !o.ok) return fail(Filter::kVisibility, o);
  scene.reset();
  try {
    if (o = check_executable(spec, options.executable_by); !o.ok) return fail(Filter::kExecutable, o);
  } catch (const core::InputError&) {
    throw;  // an unknown policy reference: bad input of the whole run
  } catch (const std::exception& e) {
    return Verdict{Filter::kExecutable, e.what()};
  }
  if (options.executable_by == "none") return Verdict{};  // no rollout filter
  try {
    if (o = check_at_rest(spec); !o.ok) return fail(Filter::kAtRest, o);
  } catch (const std::exception& e) {
    return Verdict{Filter::kAtRest, e.what()};
  }
  return Verdict{};
}

}  // namespace hribench::gen
