#include "policy/oracle.h"

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "human/skeleton.h"
#include "model/mjcf.h"
#include "model/model.h"

namespace hribench::policy {

using core::Pose;
using core::Quat;
using core::Vec3;

namespace {

constexpr double kTableZ = model::kTableTopZ;
constexpr double kHoldingWidth = 0.004;   // m: an opening above this with the gripper closed holds
constexpr double kReachedDistance = 0.008;  // m: a segment's end counts as reached
constexpr double kCloseTime = 0.4;        // s of full grip before checking it
constexpr double kOpenTime = 0.5;         // s to open
constexpr double kPreshapeTime = 0.3;     // s to pre-shape the fingers before closing
// Then the commanded width shrinks slowly from kPreshapeGap over the object's width to
// kSqueezeDepth under it (the fingers meet the object slower than the metrics' "moving"
// gripper rate, 0.01 m/s), then drops to 0 (full grip force).
constexpr double kPreshapeGap = 0.004;    // m
constexpr double kSqueezeRate = 0.009;    // m/s
constexpr double kSqueezeDepth = 0.006;   // m
constexpr double kPalmDistance = 0.08;
constexpr double kHousingClearance = -0.03;  // m: TCP vs a container top (housing 0.044 above)
constexpr double kYieldSpeed = 0.6;         // m/s backing off from a disruption    // m: palm centre beyond the wrist along the forearm

bool is_container(const std::string& kind) { return kind == "bin" || kind == "tray" || kind == "box"; }

// Height of the TCP above an object's bottom for a top-down grasp (m), by kind.
double grasp_height(const std::string& kind, const Vec3& half) {
  if (kind == "bottle") return 0.18;   // the neck: the hand housing stays above the top
  if (kind == "cup") return 0.055;
  return half.z();
}

// Width of an object across the fingers of a top-down grasp (m).
double grip_width(const std::string& kind, const Vec3& half) {
  if (kind == "bottle") return 0.028;  // the neck
  return 2 * std::min(half.x(), half.y());
}

// Rotation vector of R (axis * angle), angle in [0, pi].
Vec3 rotation_vector(const Quat& q) {
  const Eigen::AngleAxisd aa(q.normalized());
  double angle = aa.angle();
  Vec3 axis = aa.axis();
  if (angle > core::kPi) {
    angle = 2 * core::kPi - angle;
    axis = -axis;
  }
  return axis * angle;
}

double wrap_quarter(double a) {  // into [-pi/4, pi/4) modulo pi/2
  const double q = core::kPi / 2;
  return a - q * std::floor((a + q / 2) / q);
}

Vec3 clamp_norm(const Vec3& v, double limit) {
  const double n = v.norm();
  return n > limit ? Vec3(v * (limit / n)) : v;
}

// Distance from point p to segment ab.
double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b, Vec3& closest) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  closest = a + t * ab;
  return (p - closest).norm();
}

}  // namespace

// The observation, indexed by the expert's object order.
struct ExpertPolicy::World {
  double time = 0;
  Pose X_WT;
  double width = 0;
  std::vector<Pose> objects;  // body frames (footprint centre, bottom), objects_ order
  std::array<Vec3, kHumanKeypoints> joints;
  double dt = 0.05;

  Vec3 centre(size_t i, const Vec3& half) const { return objects[i] * Vec3(0, 0, half.z()); }
  // Palm centre of a hand (0 left, 1 right) from the wrist and elbow.
  Vec3 palm(int side) const {
    const Vec3 wrist = joints[static_cast<size_t>(side == 0 ? human::index(human::Joint::kLeftWrist)
                                                            : human::index(human::Joint::kRightWrist))];
    const Vec3 elbow = joints[static_cast<size_t>(side == 0 ? human::index(human::Joint::kLeftElbow)
                                                            : human::index(human::Joint::kRightElbow))];
    const Vec3 forearm = wrist - elbow;
    return forearm.norm() > 1e-6 ? Vec3(wrist + kPalmDistance * forearm.normalized()) : wrist;
  }
};

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
  episode_ = info.episode;
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
  ssm_stopped_ = false;
  started_ = false;
  start_positions_.clear();
  current_ = plan_.size() + 1;  // forces begin_step on the first act()
  phase_ = 0;
  phase_start_ = 0;
  latched_valid_ = false;
  speed_ = kMaxSpeed;
  gripper_ = 1.0;
  velocity_ = Vec3::Zero();
  retries_ = 0;
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
      for (auto& [name, value] : predicates_) {
        if (name == e.name) {
          value = e.detail == "true";
          found = true;
        }
      }
      if (!found) predicates_.emplace_back(e.name, e.detail == "true");
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
  switch (step.kind) {
    case StepKind::kPlace:
    case StepKind::kPutBack:
    case StepKind::kRelease:
    case StepKind::kHome:
      return false;  // the skill finishes its retreat / stays
    case StepKind::kPick:
      return ended && !(i == current_ && phase_ == 2);  // a grasp being closed is finished
    default:
      return ended;
  }
}

bool ExpertPolicy::step_dropped(size_t i) const {
  return !plan_[i].dropped_by.empty() && seen(plan_[i].dropped_by);
}

void ExpertPolicy::set_phase(int phase, double time) {
  phase_ = phase;
  phase_start_ = time;
}

void ExpertPolicy::restart_approach() {
  // Descending (1) or lowering (11) restart from above the grasp (0) or the target (10).
  if (phase_ == 1) phase_ = 0;
  if (phase_ == 11) phase_ = 10;
}

void ExpertPolicy::begin_step(size_t i, const World& world) {
  current_ = i;
  set_phase(0, world.time);
  retries_ = 0;
  latched_valid_ = false;
  latched_target_valid_ = false;
  spot_valid_ = false;
  if (i < plan_.size()) {
    for (size_t k = 0; k < objects_.size(); ++k) {
      if (objects_[k].name == plan_[i].object) {
        latched_ = world.objects[k].translation;
        latched_valid_ = true;
      }
      if (objects_[k].name == plan_[i].target) {
        latched_target_ = world.objects[k].translation;
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
  if (current_ < plan_.size()) {
    const PlanStep& step = plan_[current_];
    if (!step.after.empty() && !seen(step.after)) hold = true;
    if (!step.pause_on.empty() && seen(step.pause_on)) hold = true;
  }
  // A grasp being closed is finished first (lifting a half-closed grasp drops the object).
  const bool closing = phase_ == 2 && current_ < plan_.size();
  const bool yielding = competence_ == Competence::kOracle && disruption_running() && !closing;
  if (yielding) {
    restart_approach();
    // Yield to an intruding person: back off toward the robot's side of the table and wait.
    // Straight up first when low (the fingers may be around an object), then back.
    const Vec3 tcp = world.X_WT.translation;
    target_.translation = tcp.z() < kYieldZ - 0.03
                              ? Vec3(tcp.x(), tcp.y(), kYieldZ)
                              : Vec3(std::min(tcp.x(), kYieldX), std::clamp(tcp.y(), -0.35, 0.35),
                                     std::max(tcp.z(), kYieldZ));
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
  const double scale = yielding ? 1.0 : separation_scale(world, retreat);
  if (retreat.norm() > 0) restart_approach();
  return ActionChunk{ActionSpace::kEeDelta, {motion_action(world, scale, retreat)}};
}

void ExpertPolicy::run_step(const World& world) {
  const PlanStep& step = plan_[current_];
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
    case StepKind::kStill:
      speed_ = 0;
      break;
  }
}

namespace {

// Index of an object by name in the observation order, or npos.
template <typename Objects>
size_t index_of(const Objects& objects, const std::string& name) {
  for (size_t k = 0; k < objects.size(); ++k) {
    if (objects[k].name == name) return k;
  }
  return static_cast<size_t>(-1);
}

}  // namespace

void ExpertPolicy::run_pick(const World& world, const std::string& object, bool close) {
  const size_t k = index_of(objects_, object);
  HRIB_CHECK(k < objects_.size()) << object;
  const ObjectGeometry& g = objects_[k];
  // Oracle: the live pose; baselines: the pose seen when the step began.
  Pose X_WO = world.objects[k];
  if (competence_ != Competence::kOracle && latched_valid_) X_WO.translation = latched_;
  const Vec3 grasp = X_WO.translation + Vec3(0, 0, grasp_height(g.kind, g.half_extents));
  // Finger axis across the cube's faces (cylinders: any).
  double yaw = 0;
  if (g.kind == "cube" || g.kind == "plank") {
    const Vec3 x_obj = X_WO.rotation * Vec3::UnitX();
    const Vec3 y_home = home_.rotation * Vec3::UnitY();
    yaw = wrap_quarter(std::atan2(x_obj.y(), x_obj.x()) - std::atan2(y_home.y(), y_home.x()) +
                       core::kPi / 2);
  }
  target_.rotation = (core::axis_angle(Vec3::UnitZ(), yaw) * home_.rotation).normalized();
  // Clear height over every other object.
  double top = kTableZ;
  for (size_t i = 0; i < objects_.size(); ++i) {
    if (i != k) top = std::max(top, world.objects[i].translation.z() + 2 * objects_[i].half_extents.z());
  }
  const double above_z = std::max(grasp.z() + kApproachHeight, top + 0.06);
  const Vec3 tcp = world.X_WT.translation;
  const double elapsed = world.time - phase_start_;
  switch (phase_) {
    case 0: {  // open, go above the grasp (rising first when low and far)
      gripper_ = 1.0;
      speed_ = kMaxSpeed;
      const Vec3 above(grasp.x(), grasp.y(), above_z);
      const double horizontal = (tcp - above).head<2>().norm();
      target_.translation = horizontal > 0.03 && tcp.z() < above_z - 0.03
                                ? Vec3(tcp.x(), tcp.y(), above_z)
                                : above;
      if ((tcp - above).norm() < 2 * kReachedDistance && world.width > 0.07) set_phase(1, world.time);
      break;
    }
    case 1:  // descend onto the grasp
      gripper_ = 1.0;
      speed_ = kFineSpeed * 1.5;
      target_.translation = grasp;
      if ((tcp - grasp).norm() < kReachedDistance / 2 ||
          (elapsed > 3.0 && (tcp - grasp).norm() < 2 * kReachedDistance)) {
        if (close) set_phase(2, world.time);
      }
      break;
    case 2:  // close on the object, then check that something is between the fingers
      // Pre-shape just wider than the object, then squeeze: the fingers touch it slowly (the
      // grasp, which ends an act, is not in the middle of a fast gripper motion).
      {
        const double w = grip_width(g.kind, g.half_extents);
        const double command = w + kPreshapeGap - kSqueezeRate * std::max(0.0, elapsed - kPreshapeTime);
        gripper_ = command > w - kSqueezeDepth ? std::min(1.0, command / kMaxGripperWidth) : 0.0;
      }
      speed_ = 0;
      target_.translation = grasp;
      if (elapsed > kPreshapeTime + (kPreshapeGap + kSqueezeDepth) / kSqueezeRate + kCloseTime) {
        if (world.width > kHoldingWidth) {
          set_phase(3, world.time);
        } else {
          ++retries_;
          set_phase(0, world.time);
        }
      }
      break;
    default: {  // lift clear
      gripper_ = 0.0;
      speed_ = kMaxSpeed * 0.6;
      target_.translation = Vec3(grasp.x(), grasp.y(), above_z + 0.05);
      if ((tcp - target_.translation).norm() < 2 * kReachedDistance) internal_done_[current_] = 1;
      break;
    }
  }
}

void ExpertPolicy::run_place(const World& world, const PlanStep& step) {
  const size_t k = index_of(objects_, step.object);
  HRIB_CHECK(k < objects_.size()) << step.object;
  const ObjectGeometry& g = objects_[k];
  const Vec3 tcp = world.X_WT.translation;
  const Vec3 centre = world.centre(k, g.half_extents);
  const bool holding = gripper_ < 0.5 && world.width > kHoldingWidth &&
                       (centre - tcp).norm() < 0.06 + g.half_extents.z();
  // Not holding it yet (or lost it before the release): pick it first.
  if (phase_ < 10) {
    if (holding && (phase_ == 0 || phase_ >= 3)) {  // already holding it, or lifting it
      set_phase(10, world.time);
    } else {
      run_pick(world, step.object, true);
      internal_done_[current_] = 0;
      if (phase_ == 3 && holding) set_phase(10, world.time);
      return;
    }
  }
  if (phase_ < 12 && !holding) {
    set_phase(0, world.time);
    run_pick(world, step.object, true);
    internal_done_[current_] = 0;
    return;
  }
  // Where the object goes: over the target's centre, onto its surface.
  Vec3 place_xy;
  double surface = kTableZ;
  double gap = 0.008;
  double container_top = -1;
  if (step.kind == StepKind::kPutBack) {
    place_xy = start_positions_[k];
  } else {
    const size_t c = index_of(objects_, step.target);
    HRIB_CHECK(c < objects_.size()) << step.target;
    Vec3 origin = world.objects[c].translation;
    if (competence_ != Competence::kOracle && latched_target_valid_) origin = latched_target_;
    const ObjectGeometry& cg = objects_[c];
    // A free spot on the target, chosen when the carry begins (the oracle: again each time).
    if (phase_ == 10 && (!spot_valid_ || world.time == phase_start_)) {
      Pose X_WC = world.objects[c];
      X_WC.translation = origin;
      spot_ = free_spot(world, k, c, X_WC);
      spot_valid_ = true;
    }
    place_xy = spot_valid_ ? spot_ : origin;
    if (is_container(cg.kind)) {
      container_top = origin.z() + 2 * cg.half_extents.z();
      surface = origin.z() + 0.008;
      gap = 0.015;
    } else {
      surface = origin.z() + 2 * cg.half_extents.z();
    }
    if (step.kind == StepKind::kHover) {
      // Short of the target on the robot side, at a safe height.
      const Vec3 toward = Vec3(origin.x(), origin.y(), 0).normalized();
      place_xy = origin - 0.22 * toward;
      surface = origin.z() + 0.12;
    }
  }
  const Vec3 offset = tcp - world.objects[k].translation;  // TCP above the object's bottom
  double top = kTableZ;
  for (size_t i = 0; i < objects_.size(); ++i) {
    if (i != k) top = std::max(top, world.objects[i].translation.z() + 2 * objects_[i].half_extents.z());
  }
  const double carry_z = top + kCarryClearance + offset.z();
  const Vec3 over(place_xy.x() + offset.x(), place_xy.y() + offset.y(), carry_z);
  const double elapsed = world.time - phase_start_;
  switch (phase_) {
    case 10: {  // carry over the target (rising first when low and far)
      gripper_ = 0.0;
      speed_ = kMaxSpeed;
      const double horizontal = (tcp - over).head<2>().norm();
      target_.translation = horizontal > 0.03 && tcp.z() < carry_z - 0.03
                                ? Vec3(tcp.x(), tcp.y(), carry_z)
                                : over;
      if ((tcp - over).norm() < 2 * kReachedDistance) set_phase(11, world.time);
      break;
    }
    case 11: {  // lower onto the surface
      gripper_ = 0.0;
      speed_ = kFineSpeed;
      // Into a container only as far as the hand housing stays above its walls.
      double down_z = surface + gap + offset.z();
      if (container_top > 0) down_z = std::max(down_z, container_top + kHousingClearance);
      const Vec3 down(over.x(), over.y(), down_z);
      target_.translation = down;
      if (step.kind == StepKind::kHover) {
        if ((tcp - down).norm() < 2 * kReachedDistance) internal_done_[current_] = 1;
        break;
      }
      if ((tcp - down).norm() < kReachedDistance / 2 || elapsed > 4.0) set_phase(12, world.time);
      break;
    }
    case 12:  // release
      gripper_ = 1.0;
      speed_ = 0;
      if (elapsed > kOpenTime) set_phase(13, world.time);
      break;
    default: {  // withdraw upward
      gripper_ = 1.0;
      speed_ = kMaxSpeed * 0.5;
      target_.translation = Vec3(tcp.x(), tcp.y(), std::max(tcp.z(), top + 0.10));
      if (elapsed > 0.8) {
        const bool ended = plan_[current_].act.empty() || seen(plan_[current_].act + ".end");
        if (ended || competence_ != Competence::kOracle) {
          internal_done_[current_] = 1;
        } else {
          set_phase(0, world.time);  // the goal does not hold: do it again from the live poses
        }
      }
      break;
    }
  }
}

Vec3 ExpertPolicy::free_spot(const World& world, size_t object, size_t target,
                             const Pose& X_WC) const {
  const Vec3& half = objects_[target].half_extents;
  const Vec3& own = objects_[object].half_extents;
  const double radius = std::max(own.x(), own.y());
  const bool container = is_container(objects_[target].kind);
  // Offsets the object's centre may take from the target's centre (its frame).
  const double lx = std::max(0.0, container ? half.x() - 0.02 - radius : half.x() - 0.6 * radius - 0.015);
  const double ly = std::max(0.0, container ? half.y() - 0.02 - radius : half.y() - 0.6 * radius - 0.015);
  const double lr = container ? 1e9 : 0.075;  // round plates: stay well inside the rim
  Vec3 best = X_WC.translation;
  double best_score = -1e9;
  constexpr int kGrid = 7;
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const Vec3 u(lx * (2.0 * i / (kGrid - 1) - 1), ly * (2.0 * j / (kGrid - 1) - 1), 0);
      if (u.norm() > lr) continue;
      const Vec3 p = X_WC * u;
      // Clearance to the other objects standing on or in the target.
      double clear = 0.03;
      for (size_t o = 0; o < objects_.size(); ++o) {
        if (o == object || o == target) continue;
        const Vec3 q = world.objects[o].translation;
        const Vec3 local = X_WC.inverse() * q;
        if (std::abs(local.x()) > half.x() + 0.05 || std::abs(local.y()) > half.y() + 0.05) continue;
        const double r = std::max(objects_[o].half_extents.x(), objects_[o].half_extents.y());
        clear = std::min(clear, (p - q).head<2>().norm() - r - radius);
      }
      const double score = clear - 0.05 * u.norm();
      if (score > best_score) {
        best_score = score;
        best = p;
      }
    }
  }
  return best;
}

void ExpertPolicy::run_home(const World& world) {
  const Vec3 tcp = world.X_WT.translation;
  gripper_ = 1.0;
  speed_ = kMaxSpeed;
  target_.rotation = home_.rotation;
  // Up first when low, then home.
  if (tcp.z() < home_.translation.z() - 0.1 && (tcp - home_.translation).head<2>().norm() > 0.05) {
    target_.translation = Vec3(tcp.x(), tcp.y(), home_.translation.z());
  } else {
    target_.translation = home_.translation;
  }
}

void ExpertPolicy::run_handover(const World& world, const PlanStep& step) {
  const size_t k = index_of(objects_, step.object);
  HRIB_CHECK(k < objects_.size()) << step.object;
  const ObjectGeometry& g = objects_[k];
  const Vec3 tcp = world.X_WT.translation;
  const Vec3 centre = world.centre(k, g.half_extents);
  const int side = step.target == "human.left" ? 0 : 1;
  const Vec3 palm = world.palm(side);
  if (step.kind == StepKind::kOffer) {
    const bool holding = gripper_ < 0.5 && world.width > kHoldingWidth &&
                         (centre - tcp).norm() < 0.06 + g.half_extents.z();
    if (phase_ < 20) {
      if (holding && (phase_ == 0 || phase_ >= 3)) {
        set_phase(20, world.time);
      } else {
        run_pick(world, step.object, true);
        internal_done_[current_] = 0;
        return;
      }
    }
    gripper_ = 0.0;
    // Hold it ready in front of the robot until the receiving hand reaches out, then bring it
    // into the palm.
    const std::string receiver = receiving_act(step.object);
    if (!receiver.empty() && !seen(receiver + ".open") && competence_ != Competence::kBlind) {
      speed_ = kMaxSpeed;
      target_.translation = Vec3(0.40, std::clamp(tcp.y(), -0.2, 0.2), 1.0);
      return;
    }
    // Over the palm first, then down into it (the hand housing stays clear of the fingers).
    speed_ = kFineSpeed * 2;
    const Vec3 into = palm + (tcp - centre) + Vec3(0, 0, 0.02);
    target_.translation = (tcp - into).head<2>().norm() > 0.03 ? Vec3(into + Vec3(0, 0, 0.10)) : into;
    return;
  }
  // Release once the hand holds it (or a second after the step's event), then withdraw.
  if (phase_ < 30) set_phase(29, world.time);
  if (phase_ == 29) {
    gripper_ = 0.0;
    speed_ = 0;
    // Blind does not watch the hand: it lets go as soon as the step begins.
    if (competence_ == Competence::kBlind || human_holds(step.object) ||
        world.time - phase_start_ > 1.0) {
      set_phase(30, world.time);
    }
    return;
  }
  const double elapsed = world.time - phase_start_;
  if (phase_ == 30) {
    gripper_ = 1.0;
    speed_ = 0;
    if (elapsed > kOpenTime) set_phase(31, world.time);
  } else {
    gripper_ = 1.0;
    speed_ = kFineSpeed * 2;
    target_.translation = Vec3(tcp.x() - 0.15, tcp.y(), tcp.z() + 0.05);
    if (elapsed > 1.0) internal_done_[current_] = 1;
  }
}

bool ExpertPolicy::human_holds(const std::string& object) const {
  for (const auto& [name, value] : predicates_) {
    if (value && name.rfind("held(human.", 0) == 0 && name.find(", " + object + ")") != std::string::npos &&
        name.find(' ', name.find(')')) == std::string::npos) {
      return true;
    }
  }
  return false;
}

std::string ExpertPolicy::receiving_act(const std::string& object) const {
  for (const auto& entry : episode_->acts) {
    const script::Act& act = entry.value;
    if (act.actor != "human" || !act.motion || !act.motion->primitive) continue;
    if (act.motion->primitive->value() != "receive") continue;
    for (const auto& param : act.motion->params) {
      const script::Expr& e = param.value.scalar.expr;
      if (param.name == "object" && e.kind == script::Expr::Kind::kString && e.text == object) {
        return entry.name;
      }
    }
  }
  return "";
}

double ExpertPolicy::separation_scale(const World& world, Vec3& retreat) const {
  retreat = Vec3::Zero();
  if (competence_ != Competence::kOracle) return 1.0;
  if (current_ < plan_.size()) {
    const StepKind kind = plan_[current_].kind;
    if (kind == StepKind::kOffer || kind == StepKind::kRelease || kind == StepKind::kApproach) return 1.0;
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
  const std::array<Segment, 9> body = {
      Segment{joint(Joint::kLeftElbow), world.palm(0), 0},
      Segment{joint(Joint::kRightElbow), world.palm(1), 0},
      Segment{joint(Joint::kLeftShoulder), joint(Joint::kLeftElbow), 0},
      Segment{joint(Joint::kRightShoulder), joint(Joint::kRightElbow), 0},
      Segment{joint(Joint::kNeck), joint(Joint::kHead), 0.06},
      Segment{joint(Joint::kHead), joint(Joint::kHead) + Vec3(0, 0, 0.1), 0.06},
      Segment{joint(Joint::kSpine3), joint(Joint::kNeck), 0.08},
      Segment{joint(Joint::kSpine1), joint(Joint::kSpine3), 0.08},
      Segment{joint(Joint::kLeftShoulder), joint(Joint::kRightShoulder), 0.02}};
  double best = 1e9;
  Vec3 away = Vec3::Zero();
  for (const Segment& segment : body) {
    for (const Vec3& p : robot) {
      Vec3 closest;
      const double d = segment_distance(p, segment.a, segment.b, closest) - segment.extra;
      if (d < best) {
        best = d;
        away = p - closest;
      }
    }
  }
  if (best < kRetreatDistance) {
    Vec3 dir = away;
    dir.z() = std::max(dir.z(), 0.0);
    retreat = dir.norm() > 1e-6 ? Vec3(dir.normalized()) : Vec3(-1, 0, 0);
    // Waiting for an event the step must start after: any motion would count as its start
    // (I3 scores even a retreat straight up as premature), so the robot holds still.
    if (holding_) retreat = Vec3::Zero();
    return 0;
  }
  if (best < kStopDistance || (ssm_stopped_ && best < kResumeDistance)) return 0;
  if (best < kSlowDistance) return 0.3 + 0.7 * (best - kStopDistance) / (kSlowDistance - kStopDistance);
  return 1.0;
}

Action ExpertPolicy::motion_action(const World& world, double scale, const Vec3& retreat) {
  const double dt = world.dt;
  const Vec3 tcp = world.X_WT.translation;
  ssm_stopped_ = scale == 0 && competence_ == Competence::kOracle && speed_ > 0;
  Vec3 desired = Vec3::Zero();
  if (retreat.norm() > 0) {
    desired = retreat * 0.15;
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
