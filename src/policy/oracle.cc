#include "policy/oracle.h"

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "model/mjcf.h"
#include "model/model.h"
#include "policy/oracle_internal.h"
#include "sim/distance.h"

namespace hribench::policy {

using namespace oracle_internal;  // NOLINT: the expert's own internals

namespace {

using Joints = std::array<Vec3, kHumanKeypoints>;

// The surface separation the oracle estimates between the robot's hand and wrist (capsules
// about the TCP pose: the hand housing 0.2 m across the fingers, the fingers, the flange and
// the wrist above) and the person's arms, hands (a ball about the wrist: the hand may point
// anywhere), head and chest, m; `away` is the unit direction from the person's nearest point
// to the robot's (the motion that increases it).
double intrusion_gap(const Pose& X_WT, const Joints& joints, Vec3& away) {
  const Vec3 tcp = X_WT.translation;
  const Vec3 up = X_WT.rotation * Vec3(0, 0, -1);
  const Vec3 across = X_WT.rotation * Vec3(0, 1, 0);
  const Vec3 housing = tcp + (skill_robot().gripper.tcp_offset - 0.035) * up;
  const std::array<GapCapsule, 4> robot = {
      GapCapsule{housing - 0.07 * across, housing + 0.07 * across, 0.035}, GapCapsule{tcp, tcp + 0.05 * up, 0.02},
      GapCapsule{tcp + 0.11 * up, tcp + 0.2 * up, 0.06}, GapCapsule{tcp + 0.2 * up, tcp + 0.32 * up, 0.06}};
  using human::Joint;
  const auto joint = [&](Joint j) { return joints[static_cast<size_t>(human::index(j))]; };
  const Vec3 head = joint(Joint::kHead);
  const std::array<GapCapsule, 9> body = {
      GapCapsule{joint(Joint::kLeftWrist), joint(Joint::kLeftWrist), kHandReach},
      GapCapsule{joint(Joint::kRightWrist), joint(Joint::kRightWrist), kHandReach},
      GapCapsule{joint(Joint::kLeftElbow), joint(Joint::kLeftWrist), 0.04},
      GapCapsule{joint(Joint::kRightElbow), joint(Joint::kRightWrist), 0.04},
      GapCapsule{joint(Joint::kLeftShoulder), joint(Joint::kLeftElbow), 0.05},
      GapCapsule{joint(Joint::kRightShoulder), joint(Joint::kRightElbow), 0.05},
      GapCapsule{head, head + Vec3(0, 0, 0.06), 0.1},
      GapCapsule{joint(Joint::kSpine3), joint(Joint::kNeck), 0.12},
      GapCapsule{joint(Joint::kSpine1), joint(Joint::kSpine3), 0.11}};
  away = Vec3(-1, 0, 0);
  return surface_gap(robot, body, away);
}

// The largest speed toward a person at which the robot keeps docs/metrics.md's protective
// separation distance S_p (human speed 2.0 m/s within 0.5 m, else 1.6; reaction 0.1 s,
// stopping at 3 m/s^2, 0.05 m intrusion and uncertainty) at separation d, m/s.
double protective_speed(double d) {
  const double v_h = d < 0.5 ? 2.0 : 1.6;
  const double a = 1.0 / 6;
  const double b = v_h / 3 + 0.1;
  const double c = 0.1 * v_h + 0.05 - d;
  return c >= 0 ? 0.0 : (-b + std::sqrt(b * b - 4 * a * c)) / (2 * a);
}

// Yielding to an intruding person: the speed scale toward the yield pose `target` (commanded
// at `speed`), or 0 and a back-off direction `retreat` (times kRetreatSpeed) when the estimated
// separation is below kProtectiveGap. Backing off moves away from the person, never down
// (rising a little when low: the fingers may be beside an object), and stays in the robot's
// half of the workspace.
double yield_scale(const Pose& X_WT, const Joints& joints, const Vec3& target, double speed, Vec3& retreat) {
  retreat = Vec3::Zero();
  Vec3 away;
  const double gap = intrusion_gap(X_WT, joints, away);
  const Vec3 tcp = X_WT.translation;
  if (gap < kProtectiveGap) {
    Vec3 dir = away;
    dir.z() = std::max(dir.z(), tcp.z() < kYieldZ - 0.03 ? 0.3 : 0.0);
    if (tcp.x() < kYieldX - 0.1) dir.x() = std::max(dir.x(), 0.0);
    if (std::abs(tcp.y()) > 0.45 && dir.y() * tcp.y() > 0) dir.y() = 0;
    if (tcp.z() > kYieldZ + 0.25) dir.z() = std::min(dir.z(), 0.0);
    if (dir.norm() > 1e-6) retreat = kIntrusionRetreatFactor * dir.normalized();
    return 0;
  }
  const Vec3 to_go = target - tcp;
  if (to_go.norm() < 1e-3 || speed <= 0) return 1.0;
  // The rate at which the motion closes the gap (m per m), from 1 cm along it.
  Pose ahead = X_WT;
  ahead.translation = tcp + 0.01 * to_go.normalized();
  Vec3 unused;
  const double closing = (gap - intrusion_gap(ahead, joints, unused)) / 0.01;
  if (closing <= 0) return 1.0;
  return std::clamp(protective_speed(gap - kGapMargin) / (closing * speed), 0.0, 1.0);
}

}  // namespace

ExpertPolicy::ExpertPolicy(Competence competence) : competence_(competence) {}

PolicySpec ExpertPolicy::spec() const {
  PolicySpec spec;
  spec.state_track = true;
  spec.privileged = true;
  spec.action_space = ActionSpace::kEeDelta;
  spec.replan_every = 1;
  return spec;
}

void ExpertPolicy::reset(const EpisodeInfo& info) {
  if (!info.episode) {
    throw PolicyError(PolicyErrorKind::kFailed,
                      std::string(to_string(competence_)) + ": needs the privileged episode");
  }
  if (info.robot != skill_robot().name) {
    throw PolicyError(PolicyErrorKind::kFailed, std::string(to_string(competence_)) +
                                                    ": has skills for " + skill_robot().name +
                                                    ", not " + info.robot);
  }
  episode_ = info.episode;
  body_ = human::Skeleton::FromHeight(episode_->human.height.value());
  control_dt_ = info.control_dt;
  try {
    plan_ = make_plan(*episode_, competence_);
  } catch (const core::InputError& e) {
    throw PolicyError(PolicyErrorKind::kFailed, std::string(to_string(competence_)) + ": " + e.what());
  }
  objects_.clear();
  for (const auto& entry : episode_->scene.objects) {
    ObjectGeometry g;
    g.name = entry.name;
    g.kind = entry.value.kind.value();
    const std::optional<model::ObjectKind> kind = model::object_kind_from_name(g.kind);
    g.half_extents = kind ? model::mjcf::nominal_half_extents(*kind) : Vec3(0.03, 0.03, 0.03);
    // A platform is a fixed box on the table top, sized and placed by the script.
    const script::SceneObject& o = entry.value;
    if (g.kind == "platform" && o.size.size() == 3 && o.pose && o.pose->xy.size() == 2) {
      g.half_extents = Vec3(o.size[0].value(), o.size[1].value(), o.size[2].value()) / 2;
      Pose X_WO = Pose::Identity();
      X_WO.translation = Vec3(o.pose->xy[0].value(), o.pose->xy[1].value(),
                              model::kTableTopZ + g.half_extents.z());
      X_WO.rotation = core::axis_angle(Vec3::UnitZ(), o.pose->yaw_deg.value() * core::kPi / 180);
      g.fixed_X_WO = X_WO;
    }
    objects_.push_back(g);
  }
  events_.clear();
  predicates_.clear();
  internal_done_.assign(plan_.size(), 0);
  events_read_ = 0;
  stopped_ = false;
  holding_ = false;
  waiting_ = false;
  ssm_stopped_ = false;
  started_ = false;
  start_positions_.clear();
  current_ = plan_.size() + 1;  // forces begin_step on the first act()
  phase_ = PickPhase::kApproach;
  phase_start_ = 0;
  latched_valid_ = false;
  believed_.clear();
  speed_ = kMaxSpeed;
  gripper_ = 1.0;
  velocity_ = Vec3::Zero();
  palms_time_ = -1;
}

const ExpertPolicy::ObjectGeometry* ExpertPolicy::geometry(const std::string& name) const {
  for (const ObjectGeometry& g : objects_) {
    if (g.name == name) return &g;
  }
  return nullptr;
}

void ExpertPolicy::update_events(const Observation& observation) {
  for (; events_read_ < observation.events.size(); ++events_read_) {
    const ScriptEvent& e = observation.events[events_read_];
    if (e.kind == "predicate_change") {
      bool found = false;
      for (LoggedPredicate& p : predicates_) {
        if (p.name == e.name) {
          p.value = e.detail == "true";
          found = true;
        }
      }
      if (!found) {
        // The name is the predicate's text, bound to the episode's objects as the script was.
        std::vector<std::string> names;
        for (const ObjectGeometry& g : objects_) names.push_back(g.name);
        predicates_.push_back(
            {e.name, script::holding_atom(script::bind_predicate(e.name, names).root), e.detail == "true"});
      }
      continue;
    }
    if (e.kind == "warning") continue;
    if ((e.kind == "cue" || e.kind == "act_start") && competence_ != Competence::kBlind) {
      // A stop gesture halts the robot from its start (the cue is its held phase; the robot
      // must already be still then); a go cue resumes. Stop cues of acts that contradict are
      // handled by the plan (dropped steps).
      const std::string act = e.name.substr(0, e.name.find('.'));
      for (const auto& entry : episode_->acts) {
        const script::Act& a = entry.value;
        if (entry.name != act || !a.cue || a.contradicts) continue;
        if (a.cue->kind == "stop") stopped_ = true;
        if (a.cue->kind == "go" && e.kind == "cue") stopped_ = false;
      }
    }
    events_.push_back(e.name);
  }
}

bool ExpertPolicy::seen(const std::string& event) const {
  return std::find(events_.begin(), events_.end(), event) != events_.end();
}

bool ExpertPolicy::disruption_running() const {
  for (const auto& entry : episode_->acts) {
    // Stop gestures (I4) are disruptions too, obeyed by standing still, not by backing off.
    const bool stop = entry.value.cue && entry.value.cue->kind == "stop";
    if (entry.value.actor == "human" && entry.value.disruption && !stop && seen(entry.name + ".start") &&
        !seen(entry.name + ".end")) {
      return true;
    }
  }
  return false;
}

bool ExpertPolicy::step_done(size_t i) const {
  const PlanStep& step = plan_[i];
  if (internal_done_[i]) return true;
  if (step.act.empty()) return false;
  const bool ended = seen(step.act + ".end");
  // Taking from a hand: run_take finishes them (an open gripper touching it is not a grasp).
  if ((step.kind == StepKind::kPick || step.kind == StepKind::kApproach) && starts_in_hand(step.object)) return false;
  switch (step.kind) {
    case StepKind::kPlace:
    case StepKind::kPutBack:
    case StepKind::kOffer:
    case StepKind::kRelease:
    case StepKind::kHome:
    case StepKind::kCoCarry:
      return false;  // the skill finishes its retreat / stays / brings it into the palm
    case StepKind::kPick:
      return ended && !(i == current_ && closing_grasp());  // a grasp being closed is finished
    default:
      return ended;
  }
}

bool ExpertPolicy::step_dropped(size_t i) const {
  return !plan_[i].dropped_by.empty() && seen(plan_[i].dropped_by);
}

void ExpertPolicy::set_phase(SkillPhase phase, double time) {
  phase_ = phase;
  phase_start_ = time;
}

void ExpertPolicy::restart_approach() {
  // Descending, lowering or creeping restart from above the grasp, the target or the ready
  // point (the phase's start time kept).
  if (in_phase(PickPhase::kDescend)) phase_ = PickPhase::kApproach;
  if (in_phase(PlacePhase::kLower)) phase_ = PlacePhase::kCarry;
  if (in_phase(BoxWaitPhase::kCreep)) phase_ = BoxWaitPhase::kToReady;
}

void ExpertPolicy::begin_step(size_t i, const World& world) {
  current_ = i;
  set_phase(PickPhase::kApproach, world.time);
  latched_valid_ = false;
  latched_target_valid_ = false;
  latched_palm_valid_ = false;
  spot_valid_ = false;
  // The baselines' world model: refreshed here until a disruption has started, then kept.
  bool disrupted = false;
  for (const auto& entry : episode_->acts) {
    disrupted = disrupted || (entry.value.actor == "human" && entry.value.disruption && seen(entry.name + ".start"));
  }
  if (competence_ == Competence::kOracle || !disrupted || believed_.size() != objects_.size()) {
    believed_.clear();
    for (size_t k = 0; k < objects_.size(); ++k) believed_.push_back(world.objects[k].translation);
  }
  if (i < plan_.size()) {
    for (size_t k = 0; k < objects_.size(); ++k) {
      if (objects_[k].name == plan_[i].object) {
        latched_ = believed_[k];
        latched_valid_ = true;
      }
      if (objects_[k].name == plan_[i].target) {
        latched_target_ = believed_[k];
        latched_target_valid_ = true;
      }
    }
  }
}

ActionChunk ExpertPolicy::act(const Observation& observation) {
  HRIB_CHECK(episode_ != nullptr) << "act before reset";
  HRIB_CHECK(observation.state.has_value()) << "the expert needs the state track";
  update_events(observation);
  World world;
  world.time = observation.time;
  world.dt = control_dt_;
  world.X_WT = observation.proprio.X_WT;
  world.width = observation.proprio.gripper_width;
  world.joints = observation.state->human_joints_W;
  world.objects.assign(objects_.size(), Pose::Identity());
  for (size_t k = 0; k < objects_.size(); ++k) {
    if (objects_[k].fixed_X_WO) world.objects[k] = *objects_[k].fixed_X_WO;
  }
  for (const ObjectPose& pose : observation.state->objects) {
    for (size_t k = 0; k < objects_.size(); ++k) {
      if (objects_[k].name == pose.name) world.objects[k] = pose.X_WO;
    }
  }
  if (!started_) {
    started_ = true;
    home_ = world.X_WT;
    reference_ = world.X_WT.translation;
    target_ = home_;
    for (const Pose& p : world.objects) start_positions_.push_back(p.translation);
  }

  // The current step: the first neither done nor dropped.
  size_t next = 0;
  while (next < plan_.size() && (step_done(next) || step_dropped(next))) ++next;
  if (next != current_) begin_step(next, world);

  bool hold = stopped_;
  waiting_ = false;
  if (current_ < plan_.size()) {
    const PlanStep& step = plan_[current_];
    waiting_ = !stopped_ && !step.after.empty() && !seen(step.after);
    if (waiting_) hold = true;
    if (!step.pause_on.empty() && seen(step.pause_on)) hold = true;
  }
  // A grasp being closed is finished first (lifting a half-closed grasp drops the object).
  bool closing = closing_grasp() && current_ < plan_.size();
  const bool disrupted = competence_ == Competence::kOracle && disruption_running();
  // ... except when a person reaches in: a top-down grasp of an object on the table is cut
  // short at once, the fingers gripping what they already touch (the robot backs off holding
  // it) or opening (the pick starts over once the person has left).
  if (closing && disrupted) {
    const PlanStep& step = plan_[current_];
    const size_t k = index_of(objects_, step.object);
    const bool table_pick = (step.kind == StepKind::kPick || step.kind == StepKind::kPlace ||
                             step.kind == StepKind::kPutBack) &&
                            k < objects_.size() && !starts_in_hand(step.object) &&
                            box_containing(world, k) >= objects_.size();
    if (table_pick) {
      const bool touching = world.width < grip_width(objects_[k].kind, objects_[k].half_extents) + 0.002;
      gripper_ = touching ? 0.0 : 1.0;
      set_phase(touching ? PickPhase::kLift : PickPhase::kApproach, world.time);
      closing = false;
    }
  }
  const bool yielding = disrupted && !closing;
  if (yielding) {
    restart_approach();
    // Yield to an intruding person: back off toward the robot's side of the table and wait.
    // Straight up first when low (the fingers may be around an object), then back.
    const Vec3 tcp = world.X_WT.translation;
    target_.translation = tcp.z() < kYieldZ - 0.03
                              ? Vec3(tcp.x(), tcp.y(), kYieldZ)
                              : Vec3(std::min(tcp.x(), kYieldX), std::clamp(tcp.y(), -0.35, 0.35),
                                     std::max(tcp.z(), kYieldZ));
    // Wait beside the intruding hand, not in front of it: sideways, away from each palm.
    for (int side = 0; side < 2 && tcp.z() >= kYieldZ - 0.03; ++side) {
      const Vec3 palm = world.palm(side);
      const double dx = target_.translation.x() - palm.x();
      const double dy = target_.translation.y() - palm.y();
      if (std::hypot(dx, dy) >= kYieldClearance) continue;
      const double away = dy != 0 ? std::copysign(1.0, dy) : (palm.y() > 0 ? -1.0 : 1.0);
      target_.translation.y() = std::clamp(
          palm.y() + away * std::sqrt(kYieldClearance * kYieldClearance - dx * dx), -0.45, 0.45);
    }
    speed_ = kYieldSpeed;
  } else if (hold) {
    // Stop where the robot is, the gripper as commanded.
    if (!holding_) {
      reference_ = world.X_WT.translation;
      velocity_ = Vec3::Zero();
    }
    target_.translation = reference_;
    speed_ = 0;
  } else if (current_ < plan_.size()) {
    run_step(world);
  } else {
    speed_ = 0;  // all done: stay
  }

  holding_ = hold;
  Vec3 retreat = Vec3::Zero();
  const double scale = yielding ? yield_scale(world.X_WT, world.joints, target_.translation, speed_, retreat)
                                : separation_scale(world, retreat);
  if (retreat.norm() > 0) restart_approach();
  return ActionChunk{ActionSpace::kEeDelta, {motion_action(world, scale, retreat)}};
}

void ExpertPolicy::run_step(const World& world) {
  const PlanStep& step = plan_[current_];
  if (run_box_step(world, step)) return;
  if (run_take(world, step)) return;
  switch (step.kind) {
    case StepKind::kPick:
      run_pick(world, step.object, true);
      break;
    case StepKind::kApproach:
      run_pick(world, step.object, false);
      break;
    case StepKind::kPlace:
    case StepKind::kPutBack:
    case StepKind::kHover:
      run_place(world, step);
      break;
    case StepKind::kOffer:
    case StepKind::kRelease:
      run_handover(world, step);
      break;
    case StepKind::kHome:
      run_home(world);
      break;
    case StepKind::kCoCarry:
      run_co_carry(world, step);
      break;
    case StepKind::kLeave:
      run_leave(world, step);
      break;
    case StepKind::kStill:
      speed_ = 0;
      break;
  }
}

Vec3 ExpertPolicy::without_approach(const World& world, const Vec3& direction) const {
  if (current_ >= plan_.size()) return Vec3::Zero();
  const PlanStep& step = plan_[current_];
  // The metrics read any motion as the start of an act whose goal has no position (a put-back
  // on the table, going home, staying still).
  if (step.kind == StepKind::kPutBack || step.kind == StepKind::kHome || step.kind == StepKind::kStill) {
    return Vec3::Zero();
  }
  const Vec3 tcp = world.X_WT.translation;
  Vec3 d = direction;
  bool goal = false;
  for (const std::string& name : {step.object, step.target}) {
    const size_t k = index_of(objects_, name);
    if (k >= objects_.size()) continue;
    goal = true;
    const Vec3 to_goal = world.centre(k, objects_[k].half_extents) - tcp;
    if (to_goal.norm() < 1e-6) return Vec3::Zero();
    // At least a fifth of the motion away from the goal.
    const Vec3 g = to_goal.normalized();
    const double toward = d.dot(g);
    if (toward > -0.2) d -= (toward + 0.2) * g;
  }
  return goal && d.norm() > 0.2 ? Vec3(d.normalized()) : Vec3::Zero();
}

double ExpertPolicy::separation_scale(const World& world, Vec3& retreat) const {
  retreat = Vec3::Zero();
  if (competence_ != Competence::kOracle) return 1.0;
  if (current_ < plan_.size()) {
    const StepKind kind = plan_[current_].kind;
    if (kind == StepKind::kOffer || kind == StepKind::kRelease || kind == StepKind::kApproach) return 1.0;
    // Carrying an object together: the person is the partner at its other end (object-mediated,
    // the hands 0.5 m away along it) and the robot's end moves only as theirs does; stopping
    // would tilt or drop it.
    if (kind == StepKind::kCoCarry) return 1.0;
    // Taking an object from a person's hand: the hand is the goal, not an intrusion.
    const size_t k = index_of(objects_, plan_[current_].object);
    if (k < objects_.size()) {
      const Vec3 centre = world.centre(k, objects_[k].half_extents);
      if ((centre - world.palm(0)).norm() < 0.15 || (centre - world.palm(1)).norm() < 0.15) return 1.0;
    }
  }
  // Robot points: the TCP, the hand housing, the wrist and forearm above it.
  const Vec3 tcp = world.X_WT.translation;
  const Vec3 up = world.X_WT.rotation * Vec3(0, 0, -1);
  const std::array<Vec3, 4> robot = {tcp, tcp + 0.08 * up, tcp + 0.2 * up, tcp + 0.32 * up};
  // Human body segments (joint to joint, the palm beyond the wrist) with their radii beyond
  // an arm's (the distances below are for arm segments).
  using human::Joint;
  struct Segment {
    Vec3 a, b;
    double extra = 0;
  };
  const auto joint = [&](Joint j) { return world.joints[static_cast<size_t>(human::index(j))]; };
  // The arm holding a box's lid open is expected near: it only has to be kept clear of (below).
  const int lid = lid_arm(world);
  const auto arm = [&](int side) { return side == lid || receiving_hand(side) ? -1e9 : 0.0; };
  const std::array<Segment, 9> body = {
      Segment{joint(Joint::kLeftElbow), world.palm(0), arm(0)},
      Segment{joint(Joint::kRightElbow), world.palm(1), arm(1)},
      Segment{joint(Joint::kLeftShoulder), joint(Joint::kLeftElbow), arm(0)},
      Segment{joint(Joint::kRightShoulder), joint(Joint::kRightElbow), arm(1)},
      Segment{joint(Joint::kNeck), joint(Joint::kHead), 0.06},
      Segment{joint(Joint::kHead), joint(Joint::kHead) + Vec3(0, 0, 0.1), 0.06},
      Segment{joint(Joint::kSpine3), joint(Joint::kNeck), 0.08},
      Segment{joint(Joint::kSpine1), joint(Joint::kSpine3), 0.08},
      Segment{joint(Joint::kLeftShoulder), joint(Joint::kRightShoulder), 0.02}};
  // The nearest robot point to the body (the robot shifted by `shift`), and the direction away.
  const auto nearest = [&](const Vec3& shift, Vec3& away_dir) {
    double nearest_d = 1e9;
    for (const Segment& segment : body) {
      for (const Vec3& p : robot) {
        Vec3 closest;
        const double d = segment_distance(p + shift, segment.a, segment.b, closest) - segment.extra;
        if (d < nearest_d) {
          nearest_d = d;
          away_dir = p + shift - closest;
        }
      }
    }
    return nearest_d;
  };
  Vec3 away = Vec3::Zero();
  const double best = nearest(Vec3::Zero(), away);
  // Waiting for the event a step must start after, the robot has nothing to do: it backs off
  // from a person coming closer than kSlowDistance, faster (kWaitingRetreatFactor), and only by
  // motion that does not approach the step's object or target (that would be the step's
  // response onset, docs/metrics.md): back and up from a demonstrator leaning in (I3). Held by a
  // stop cue or paused by a contradiction it does not move at all (any motion would count as
  // the start of an act whose goal has no position, such as I5's put-back).
  const bool waiting = holding_ && waiting_;
  if (best < kRetreatDistance || (waiting && best < kSlowDistance)) {
    Vec3 dir = away;
    dir.z() = std::max(dir.z(), 0.0);
    retreat = dir.norm() > 1e-6 ? Vec3(dir.normalized()) : Vec3(-1, 0, 0);
    if (holding_) retreat = waiting ? Vec3(kWaitingRetreatFactor * without_approach(world, retreat)) : Vec3::Zero();
    return 0;
  }
  if (best < kStopDistance || (ssm_stopped_ && best < kResumeDistance)) {
    // Motion away from the person back toward the robot's base is not stopped (ISO/TS 15066
    // SSM stops approaching motion): slowly, when 2 cm along the commanded direction every
    // robot point would be farther from the body.
    const Vec3 to_go = target_.translation - tcp;
    const bool homeward = target_.translation.head<2>().norm() < tcp.head<2>().norm() - 0.01;
    // A person asking for the object with a gesture (I2) waits leaning in for it: picking it
    // goes on likewise (down onto it, away from their head), or neither would ever move.
    const bool asked = palm_shown(0) || palm_shown(1);
    Vec3 unused;
    if (speed_ > 0 && (homeward || asked) && to_go.norm() > 0.01 &&
        nearest(0.02 * to_go.normalized(), unused) > best + 0.005) {
      return kSeparatingScale;
    }
    // Recovery: lowering an object onto its target, or descending onto a grasp, straight down
    // goes on slowly while it brings the robot closer to the person by at most a quarter of its
    // travel (I5: a person who pointed at the tray stands near it; closer than
    // kRetreatDistance the robot backs off as above).
    const bool lowering = final_approach() && to_go.head<2>().norm() < 0.02 && to_go.z() < -0.005;
    if (speed_ > 0 && lowering && nearest(0.02 * to_go.normalized(), unused) >= best - 0.005) {
      return kSeparatingScale;
    }
    return 0;
  }
  if (lid >= 0 && lid_arm_distance(world, robot, lid) < kLidArmClearance) return 0;
  if (best < kSlowDistance) return 0.3 + 0.7 * (best - kStopDistance) / (kSlowDistance - kStopDistance);
  return 1.0;
}

Action ExpertPolicy::motion_action(const World& world, double scale, const Vec3& retreat) {
  const double dt = world.dt;
  const Vec3 tcp = world.X_WT.translation;
  ssm_stopped_ = scale == 0 && competence_ == Competence::kOracle && speed_ > 0;
  Vec3 desired = Vec3::Zero();
  if (retreat.norm() > 0) {
    desired = retreat * kRetreatSpeed;  // |retreat| > 1: faster (waiting)
  } else if (speed_ > 0 && scale > 0) {
    const Vec3 to_go = target_.translation - reference_;
    const double distance = to_go.norm();
    const double v = std::min(speed_ * scale, std::sqrt(2 * kAcceleration * distance));
    if (distance > 1e-6) desired = to_go / distance * std::min(v, distance / dt);
  }
  // Acceleration-limited velocity of the reference point.
  velocity_ += clamp_norm(desired - velocity_, kAcceleration * dt * (retreat.norm() > 0 || speed_ > kMaxSpeed ? 3 : 1));
  if (speed_ == 0 && retreat.norm() == 0) velocity_ = Vec3::Zero();
  reference_ += velocity_ * dt;
  // The reference never runs far ahead of the TCP (no wind-up when blocked).
  reference_ = tcp + clamp_norm(reference_ - tcp, 0.04);
  Action action(7, 0.0);
  const Vec3 d = clamp_norm(reference_ - tcp, 0.049);
  for (int i = 0; i < 3; ++i) action[static_cast<size_t>(i)] = std::clamp(d[i], -0.049, 0.049);
  const Vec3 r = clamp_norm(rotation_vector(target_.rotation * world.X_WT.rotation.conjugate()),
                            kMaxTurnPerStep);
  for (int i = 0; i < 3; ++i) action[static_cast<size_t>(3 + i)] = r[i];
  action[6] = gripper_;
  return action;
}

std::unique_ptr<Policy> make_expert(Competence competence) {
  return std::make_unique<ExpertPolicy>(competence);
}

}  // namespace hribench::policy
