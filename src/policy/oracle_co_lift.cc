// The expert's co-carry skill (C4 co_lift): hold the robot's end of an object that the person
// carries by the other end, keep it level with their end, set it down together, let go.
//
// One skill runs through the consecutive kCoCarry steps (one per robot act on the object):
// grasp the robot's end top-down by finger contact, then
//   oracle   — once the person's lift cue has come, command the TCP every control step so that
//              the robot's grip stays level with the person's grip at the fixed distance along
//              the object's start direction (the person's end is read from the object pose);
//              a step ends when its act's goal has held and the next act's `after` event has
//              come, so following never pauses between acts; lets go with the person (the
//              person's lowering act's `release` phase: the object rests on the target), then
//              withdraws up and back.
//   reactive,
//   blind    — move the robot's end along the nominal path of each act's goal, from the pose
//              seen when the act begins (grasped: hold; moved: up to carrying height; near: over
//              the target; on: down onto it, open, withdraw), at a fixed speed, not watching the
//              person's end (reactive after each act's `after` event, blind at once).
#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "policy/oracle.h"
#include "policy/oracle_internal.h"
#include "script/predicate.h"

namespace hribench::policy {

using namespace oracle_internal;  // NOLINT: the expert's own internals

namespace {

constexpr double kEndInset = 0.025;      // m: the robot's grip centre in from its end
constexpr double kPartnerInset = 0.03;   // m: the person's grip point in from their end
// The grasp must be closed before the person lifts (as early as 2.4 s into an episode): the
// transit to the robot's end (far from the person) is faster than the usual one, the approach
// lower, and the fingers pre-shape during the last centimetres of the descent.
constexpr double kTransitSpeed = 0.5;    // m/s
constexpr double kEndApproach = 0.05;    // m above the grip
constexpr double kPreshapeFrom = 0.015;  // m above the grip
// The grasp (both pads touching) ends the first act, and the lift act would start at the first
// gripper motion after it: the pre-shaped fingers settle before the squeeze (catching up on
// the pre-shape they closed faster than the squeeze rate across the touch in some episodes).
constexpr double kEndSettle = 0.15;      // s
constexpr double kPartnerLead = 0.10;    // s: how far ahead of the person's end the robot's aims
constexpr double kMaxLead = 0.04;        // m
constexpr double kTremorSpeed = 0.12;    // m/s: palm speeds up to this lead nothing
constexpr double kHoldingPalm = 0.15;    // m: a palm this close to the person's grip point holds it

// What a co-carry act's goal asks of the robot's end (nominal path of the baselines).
enum class Stage { kGrasp, kLift, kOver, kOnto };

Stage stage_of(const script::EpisodeSpec& episode, const std::string& act,
               const std::vector<std::string>& objects) {
  for (const auto& entry : episode.acts) {
    if (entry.name != act || !entry.value.goal) continue;
    const script::BoundPredicate goal = script::bind_predicate(entry.value.goal->source, objects);
    std::vector<const script::Predicate*> open = {&goal.root};
    bool moved = false, near = false;
    while (!open.empty()) {
      const script::Predicate* p = open.back();
      open.pop_back();
      if (p->atom == script::Atom::kAnd) {
        for (const script::Predicate& child : p->children) open.push_back(&child);
      } else if (p->atom == script::Atom::kOn || p->atom == script::Atom::kIn) {
        return Stage::kOnto;
      } else {
        moved = moved || p->atom == script::Atom::kMoved;
        near = near || p->atom == script::Atom::kNear;
      }
    }
    if (near) return Stage::kOver;
    if (moved) return Stage::kLift;
  }
  return Stage::kGrasp;
}

// The angle a, modulo pi, into [-pi/2, pi/2).
double wrap_half(double a) { return a - core::kPi * std::floor((a + core::kPi / 2) / core::kPi); }

}  // namespace

void ExpertPolicy::run_co_carry(const World& world, const PlanStep& step) {
  const size_t k = index_of(objects_, step.object);
  HRIB_CHECK(k < objects_.size()) << step.object;
  const Vec3& half = objects_[k].half_extents;
  const Pose& X_WO = world.objects[k];
  const Vec3 tcp = world.X_WT.translation;
  const double elapsed = world.time - phase_start_;

  // The robot's end: the one farther from the person (their pelvis).
  const Vec3 pelvis = world.joints[static_cast<size_t>(human::index(human::Joint::kPelvis))];
  const Vec3 plus = X_WO * Vec3(half.x(), 0, half.z());
  const Vec3 minus = X_WO * Vec3(-half.x(), 0, half.z());
  const double side = (plus - pelvis).head<2>().norm() > (minus - pelvis).head<2>().norm() ? 1.0 : -1.0;
  const Vec3 grip = X_WO * Vec3(side * (half.x() - kEndInset), 0, half.z());
  // The object's start direction, horizontal, from the robot's end toward the person's.
  double yaw0 = 0;
  for (const auto& entry : episode_->scene.objects) {
    if (entry.name == step.object && entry.value.pose) yaw0 = entry.value.pose->yaw_deg.value() * core::kPi / 180;
  }
  const Vec3 axis = -side * Vec3(std::cos(yaw0), std::sin(yaw0), 0);

  const bool holding = gripper_ < 0.5 && world.width > kHoldingWidth && (tcp - grip).norm() < 0.05;
  if (!in_skill<CoCarryPhase>()) set_phase(holding ? CoCarryPhase::kHold : CoCarryPhase::kApproach, world.time);
  const CoCarryPhase phase = std::get<CoCarryPhase>(phase_);
  if (phase == CoCarryPhase::kApproach || phase == CoCarryPhase::kDescend || phase == CoCarryPhase::kClose) {
    // Fingers across the object's width at the robot's end: of the two finger yaws that do
    // (pi apart), the one nearer the hand's yaw now. Wrapped about the home yaw instead, a plank
    // square to it sat on the wrap's edge: a turn of a hundredth of a degree flipped the target
    // by pi and the wrist turned the closing grip around the object.
    const Vec3 y_obj = X_WO.rotation * Vec3::UnitY();
    const Vec3 y_home = home_.rotation * Vec3::UnitY();
    const Vec3 y_tcp = world.X_WT.rotation * Vec3::UnitY();
    const double home_yaw = std::atan2(y_home.y(), y_home.x());
    const double now = std::remainder(std::atan2(y_tcp.y(), y_tcp.x()) - home_yaw, 2 * core::kPi);
    const double yaw = now + wrap_half(std::atan2(y_obj.y(), y_obj.x()) - home_yaw - now);
    target_.rotation = (core::axis_angle(Vec3::UnitZ(), yaw) * home_.rotation).normalized();
  }
  const Vec3 above = grip + Vec3(0, 0, kEndApproach);
  switch (phase) {
    case CoCarryPhase::kApproach: {  // open, go above the robot's end (rising first when low and far)
      gripper_ = 1.0;
      speed_ = kTransitSpeed;
      const bool low_far = (tcp - above).head<2>().norm() > 0.03 && tcp.z() < above.z() - 0.03;
      target_.translation = low_far ? Vec3(tcp.x(), tcp.y(), above.z()) : above;
      if ((tcp - above).norm() < 2 * kReachedDistance && world.width > 0.07) set_phase(CoCarryPhase::kDescend, world.time);
      return;
    }
    case CoCarryPhase::kDescend:
      gripper_ = 1.0;
      speed_ = kFineSpeed * 1.5;
      target_.translation = grip;
      if ((tcp - grip).norm() < kPreshapeFrom) set_phase(CoCarryPhase::kClose, world.time);
      return;
    case CoCarryPhase::kClose: {  // pre-shape just wider than the width, squeeze slowly, check the grip
      const Grip closed = squeeze(world, 2 * half.y(), grip, kPreshapeTime + kEndSettle, kSqueezeRate, kCloseTime);
      speed_ = kFineSpeed * 1.5;  // the rest of the descent
      if (closed == Grip::kHolding) set_phase(CoCarryPhase::kHold, world.time);
      if (closed == Grip::kMissed) set_phase(CoCarryPhase::kApproach, world.time);  // again from above
      return;
    }
    case CoCarryPhase::kOpen:
      gripper_ = 1.0;
      speed_ = 0;
      if (elapsed > kOpenTime) {
        set_phase(CoCarryPhase::kWithdraw, world.time);
        target_.translation = tcp + Vec3(0, 0, 0.12) - 0.08 * axis;  // up and back, off the object
      }
      return;
    case CoCarryPhase::kWithdraw:  // then done with the object: the rest of its co-carry steps too
      gripper_ = 1.0;
      speed_ = kFineSpeed * 2;
      for (size_t i = current_; i < plan_.size() && elapsed > 1.0; ++i) {
        if (plan_[i].kind == StepKind::kCoCarry && plan_[i].object == step.object) internal_done_[i] = 1;
      }
      return;
    case CoCarryPhase::kHold:
      break;
  }

  // Holding the robot's end.
  gripper_ = 0.0;
  // The co-carry steps of this object: whether this is the last, and the `after` event of the
  // next one ("" none).
  bool last = true;
  std::string next_after;
  bool cue_seen = false;  // any co-carry step's `after` event has come (the person leads)
  for (size_t i = 0; i < plan_.size(); ++i) {
    if (plan_[i].kind != StepKind::kCoCarry || plan_[i].object != step.object) continue;
    cue_seen = cue_seen || (!plan_[i].after.empty() && seen(plan_[i].after));
    if (i > current_ && last) {
      last = false;
      next_after = plan_[i].after;
    }
  }
  // The lowering act of the person on this object ("" none): it lets go in its release phase
  // (the object rests on the target then), and so does the robot.
  std::string lowering;
  for (const auto& entry : episode_->acts) {
    const script::Act& act = entry.value;
    if (act.actor != "human" || !act.motion || !act.motion->primitive || act.motion->primitive->value() != "lower") continue;
    for (const auto& param : act.motion->params) {
      const script::Expr& e = param.value.scalar.expr;
      if (param.name == "object" && e.kind == script::Expr::Kind::kString && e.text == step.object) {
        lowering = entry.name;
      }
    }
  }
  const Vec3 tcp_O = X_WO.inverse() * tcp;  // the grip in the object's frame

  if (competence_ == Competence::kOracle) {
    if (!cue_seen) {  // gripped: wait still for the person's lift cue
      target_.translation = reference_;
      speed_ = 0;
    } else {
      // Level with the person's end, the grips' distance apart along the start direction. The
      // person's end is the profile: the reference point follows it every control step.
      const double partner_x = -side * (half.x() - kPartnerInset);
      const Vec3 partner = X_WO * Vec3(partner_x, tcp_O.y(), tcp_O.z());
      // Led by the velocity of the palms holding it over the last control step (the arm's lag;
      // the palms, unlike the object, do not move with the robot's own end), beyond the speed
      // of a hand's tremor (8-12 Hz, a few mm: not followed ahead).
      const double dt = world.time - palms_time_;
      Vec3 velocity = Vec3::Zero();
      int holding_palms = 0;
      for (int s = 0; s < 2; ++s) {
        const Vec3 palm = world.palm(s);
        if (palms_time_ >= 0 && dt > 0 && dt < 2.5 * world.dt && (palm - partner).norm() < kHoldingPalm) {
          velocity += (palm - palms_last_[static_cast<size_t>(s)]) / dt;
          ++holding_palms;
        }
        palms_last_[static_cast<size_t>(s)] = palm;
      }
      palms_time_ = world.time;
      if (holding_palms > 0) velocity /= holding_palms;
      const double speed = velocity.norm();
      const Vec3 lead = speed > kTremorSpeed ? Vec3(velocity * ((1 - kTremorSpeed / speed) * kPartnerLead)) : Vec3::Zero();
      Vec3 goal = partner + clamp_norm(lead, kMaxLead) - std::abs(partner_x - tcp_O.x()) * axis;
      // Not below the start height before the person lowers it (it lies on its support then).
      const double rest_z = start_positions_[k].z() + tcp_O.z();
      if (lowering.empty() || !seen(lowering + ".start")) goal.z() = std::max(goal.z(), rest_z);
      target_.translation = goal;
      reference_ = goal;
      speed_ = 0;
    }
    const bool ended = step.act.empty() || seen(step.act + ".end");
    if (!last && ended && (next_after.empty() || seen(next_after))) internal_done_[current_] = 1;
    // The person lets go (or, without a lowering act, the last act begins): so does the robot;
    // the last act's goal (the object resting, nobody holding it) needs that.
    if (lowering.empty() ? last : seen(lowering + ".release")) {
      set_phase(CoCarryPhase::kOpen, world.time);
      gripper_ = 1.0;
    }
    return;
  }

  // Baselines: the nominal path of this act's goal, from the pose seen when the step began.
  const Stage stage = stage_of(*episode_, step.act, [&] {
    std::vector<std::string> names;
    for (const ObjectGeometry& g : objects_) names.push_back(g.name);
    return names;
  }());
  const size_t t = index_of(objects_, step.target);
  double surface = kTableZ;
  Vec3 over = latched_;
  if (t < objects_.size()) {
    const Vec3 origin = latched_target_valid_ ? latched_target_ : world.objects[t].translation;
    surface = origin.z() + 2 * objects_[t].half_extents.z();
    over = origin;
  }
  const double carry_z = surface + kCarryClearance + tcp_O.z();
  // The robot's grip over a point where the object's centre would be.
  const auto grip_over = [&](const Vec3& centre, double z) {
    return Vec3(centre.x() - axis.x() * std::abs(tcp_O.x()), centre.y() - axis.y() * std::abs(tcp_O.x()), z);
  };
  const Vec3 start = latched_valid_ ? latched_ : X_WO.translation;  // the object when the act began
  speed_ = kFineSpeed;
  Vec3 goal = tcp;
  switch (stage) {
    case Stage::kGrasp:
      speed_ = 0;
      break;
    case Stage::kLift:
      goal = grip_over(start, carry_z);
      break;
    case Stage::kOver:  // the object's centre over the target's
      goal = grip_over(over, carry_z);
      speed_ = kFineSpeed * 2;
      break;
    case Stage::kOnto:
      goal = grip_over(start, surface + tcp_O.z() + 0.005);
      break;
  }
  target_.translation = goal;
  const bool reached = (tcp - goal).norm() < 2 * kReachedDistance;
  if (stage == Stage::kOnto && (reached || elapsed > 4.0)) set_phase(CoCarryPhase::kOpen, world.time);
  if (stage != Stage::kOnto && (reached || speed_ == 0)) internal_done_[current_] = 1;
}

}  // namespace hribench::policy
