// The expert's handover skills: offer an object into a human palm, release once the hand holds it.
#include "policy/oracle.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "core/errors.h"
#include "policy/oracle_internal.h"
#include "sim/distance.h"

namespace hribench::policy {

using namespace oracle_internal;  // NOLINT: the expert's own internals

namespace {
// Offering: the object comes down into the palm from this high above it (m), and waits this far
// short of a shown palm (horizontally, toward the robot) until the hand opens.
constexpr double kOfferAbove = 0.10;
constexpr double kOfferStandoff = 0.12;
// A receiving palm turned sideways (receive's `palm: medial`) closes its fingers across its
// whole height: the gripper's fingertips (the TCP) stay this far above the palm centre, the
// object held out below them (fingers lower got clamped against the gripper, which then could
// not open before the person pulled).
constexpr double kMedialPalmClearance = 0.05;
// Taking from a hand: the gripper waits this far short of the object (horizontally, toward the
// robot) and this high above its grasp point while the person reaches, then comes in over the
// grasp point from kTakeAbove.
constexpr double kTakeStandoff = 0.30;
constexpr double kTakeAbove = 0.07;
// ... and keeps its hand housing and wrist this far from the head of a person leaning in (m,
// to the head joint), backing off toward its base when closer.
constexpr double kTakeHeadClearance = 0.21;
// Once it holds the object the person let go of: back this far toward the base before placing.
constexpr double kTakeRetreat = 0.15;
}  // namespace

bool ExpertPolicy::starts_in_hand(const std::string& object) const {
  for (const auto& entry : episode_->scene.objects) {
    if (entry.name == object && entry.value.held_by) return entry.value.held_by->value().rfind("human.", 0) == 0;
  }
  return false;
}

namespace {
// The palm centre of a hand held out to receive (0 left, 1 right): level with the wrist (the
// hand is held level, palm up or turned in, however steeply the forearm comes down to it),
// kReceivingPalmReach beyond it along the forearm's horizontal direction turned halfway toward
// the robot's base (the fingers point from the shoulder to the receiving spot, further toward
// the robot than the bent forearm). The forearm's own line (World::palm) puts the palm of a
// forearm coming down at 35 degrees 6 cm low and short.
constexpr double kReceivingPalmReach = 0.09;
// (Wrist and elbow in world; nullopt when degenerate.)
std::optional<Vec3> receiving_palm(const Vec3& wrist, const Vec3& elbow) {
  const Vec3 forearm(wrist.x() - elbow.x(), wrist.y() - elbow.y(), 0);
  const Vec3 to_base(-wrist.x(), -wrist.y(), 0);
  if (forearm.norm() < 1e-3 || to_base.norm() < 1e-3) return std::nullopt;
  const Vec3 fingers = forearm.normalized() + 0.5 * to_base.normalized();
  if (fingers.norm() < 1e-3) return std::nullopt;
  return Vec3(wrist + kReceivingPalmReach * fingers.normalized());
}
// A hand shown palm up with a gesture (give_me, then receive) is held level, its fingers along
// the horizontal direction from the shoulder to the receiving spot (human/motion.cc): its palm
// centre lies the skeleton's palm distance beyond the wrist along that direction, level with
// the wrist (nullopt when degenerate). The hand is a capsule of kHandRadius (times the
// skeleton's scale) about that line; the robot's fingertips reach kFingertipsBelowTcp below
// its TCP.
constexpr double kHandRadius = 0.035;
constexpr double kFingertipsBelowTcp = 0.013;
constexpr double kCentreOverPalm = 0.035;
constexpr double kFingertipsIntoHand = 0.005;
std::optional<Vec3> shown_palm(const Vec3& wrist, const Vec3& shoulder, double palm_distance) {
  const Vec3 fingers(wrist.x() - shoulder.x(), wrist.y() - shoulder.y(), 0);
  if (fingers.norm() < 1e-3) return std::nullopt;
  return Vec3(wrist + palm_distance * fingers.normalized());
}
// The centre of a receive act's zone (where the person's palm is brought), or nullopt.
std::optional<Vec3> zone_centre(const script::Act& act) {
  if (!act.motion) return std::nullopt;
  for (const auto& param : act.motion->params) {
    const script::ValueTree& v = param.value;
    if (param.name != "zone") continue;
    for (size_t i = 0; i < v.keys.size() && i < v.items.size(); ++i) {
      const script::ValueTree& c = v.items[i];
      if (v.keys[i] == "center" && c.items.size() == 3) {
        return Vec3(c.items[0].scalar.expr.number, c.items[1].scalar.expr.number, c.items[2].scalar.expr.number);
      }
    }
  }
  return std::nullopt;
}
// Toward a palm shown with a gesture, from low and far (just picked): straight up to the goal's
// height first, then across to it. A diagonal rise passes under the fingers of a palm held out
// toward the robot and lifts the hand housing into them.
Vec3 rise_first(const Vec3& tcp, const Vec3& goal) {
  return tcp.z() < goal.z() - 0.03 && (goal - tcp).head<2>().norm() > 0.05 ? Vec3(tcp.x(), tcp.y(), goal.z()) : goal;
}
}  // namespace

// The horizontal direction along the hand holding an object (wrist to fingertips), or nullopt
// when the object does not sit beside the palm as a person holds it from the start: upright,
// its x axis along the hand, its centre kPalmDistance-ish beyond the wrist along it and beside
// the palm across it (model.cc's palm_hold; the hand then turns only about the vertical). A
// grasp with the fingers along it keeps the fingers and the hand housing (0.2 m along the
// finger axis) off the hand beside the object; across it (perpendicular to the wrist-object
// line, 40 degrees off) the housing's end came down onto the hand.
static std::optional<Vec3> held_along_hand(const Pose& X_WO, const Vec3& centre, const Vec3& wrist) {
  Vec3 x_obj = X_WO.rotation * Vec3::UnitX();
  if ((X_WO.rotation * Vec3::UnitZ()).z() < std::cos(kTakeUprightTilt)) return std::nullopt;
  x_obj.z() = 0;
  if (x_obj.norm() < 1e-3) return std::nullopt;
  x_obj.normalize();
  Vec3 from_wrist = centre - wrist;
  from_wrist.z() = 0;
  const double along = from_wrist.dot(x_obj);
  const double across = (from_wrist - along * x_obj).norm();
  if (along < kTakeHandAlong.first || along > kTakeHandAlong.second || across < kTakeHandAcross.first ||
      across > kTakeHandAcross.second) {
    return std::nullopt;
  }
  return x_obj;
}

// The surface gap (m) the oracle estimates between a person's head (a ball of head_radius about
// the head joint, kTakeHeadTall high) and the robot's hand and wrist at TCP pose X_WT: the hand
// housing, the fingers, link7 on the tool axis and link6 beside it toward the base (0.088 m off
// the axis, 0.2 m over the TCP: the wrist a person leaning in over the table meets first), the
// forearm from there up toward the base; `away` the unit direction from the head toward the
// robot's nearest point.
static double head_gap(const Pose& X_WT, const Vec3& head, double head_radius, Vec3& away) {
  const Vec3 tcp = X_WT.translation;
  const Vec3 up = X_WT.rotation * Vec3(0, 0, -1);
  const Vec3 across = X_WT.rotation * Vec3(0, 1, 0);
  Vec3 to_base(-tcp.x(), -tcp.y(), 0);
  to_base = to_base.norm() > 1e-6 ? Vec3(to_base.normalized()) : Vec3(-1, 0, 0);
  const Vec3 side = to_base.cross(Vec3::UnitZ());
  const Vec3 housing = tcp + 0.068 * up;
  const Vec3 link7 = tcp + 0.21 * up;
  const Vec3 link6 = link7 + 0.088 * to_base;
  const std::array<GapCapsule, 6> robot = {GapCapsule{housing - 0.07 * across, housing + 0.07 * across, 0.035},
                                           GapCapsule{tcp, tcp + 0.05 * up, 0.02},
                                           GapCapsule{tcp + 0.11 * up, link7, 0.06},
                                           GapCapsule{link7, link6, 0.06},
                                           GapCapsule{link6 - 0.06 * side, link6 + 0.06 * side, 0.06},
                                           GapCapsule{link6, link6 + 0.2 * to_base + 0.1 * up, 0.06}};
  away = -to_base;
  const std::array<GapCapsule, 1> head_ball = {GapCapsule{head, head + Vec3(0, 0, kTakeHeadTall), head_radius}};
  return surface_gap(robot, head_ball, away);
}

bool ExpertPolicy::run_take(const World& world, const PlanStep& step) {
  if (step.kind == StepKind::kPlace && starts_in_hand(step.object)) return run_take_retreat(world);
  if ((step.kind != StepKind::kApproach && step.kind != StepKind::kPick) || !starts_in_hand(step.object)) {
    return false;
  }
  const size_t k = index_of(objects_, step.object);
  HRIB_CHECK(k < objects_.size()) << step.object;
  const ObjectGeometry& g = objects_[k];
  const Pose& X_WO = world.objects[k];
  const Vec3 tcp = world.X_WT.translation;
  const Vec3 centre = world.centre(k, g.half_extents);
  // The grasp point along the object's own axis (a held object may lean in the hand).
  const Vec3 grasp = X_WO * Vec3(0, 0, grasp_height(g.kind, g.half_extents));
  // The fingers close across the object, clear of the hand beside it: the finger axis is
  // perpendicular to the horizontal direction from the nearer wrist to the object (the offered
  // object sits beside the palm, off its normal; a cube: the face-aligned yaw closest to that).
  const Vec3 wrist_l = world.joints[static_cast<size_t>(human::index(human::Joint::kLeftWrist))];
  const Vec3 wrist_r = world.joints[static_cast<size_t>(human::index(human::Joint::kRightWrist))];
  const Vec3 wrist = (wrist_l - centre).norm() < (wrist_r - centre).norm() ? wrist_l : wrist_r;
  Vec3 from_palm = centre - wrist;
  from_palm.z() = 0;
  const Vec3 y_home = home_.rotation * Vec3::UnitY();
  double yaw = 0;
  if (from_palm.norm() > 0.01) {
    // Finger axis (the hand's y) perpendicular to from_palm.
    yaw = wrap_quarter(std::atan2(from_palm.x(), -from_palm.y()) - std::atan2(y_home.y(), y_home.x()));
    if (g.kind != "cube") yaw = std::atan2(from_palm.x(), -from_palm.y()) - std::atan2(y_home.y(), y_home.x());
  }
  // (Only where the hand housing comes down near the hand's height: at a bottle's neck it
  // passes high over the hand, and that turn put the arm's wrist at its reach limit.)
  const bool housing_low = grasp_height(g.kind, g.half_extents) - g.half_extents.z() < kTakeHousingLow;
  const auto along_hand = housing_low ? held_along_hand(X_WO, centre, wrist) : std::nullopt;
  if (along_hand) {
    yaw = std::atan2(along_hand->y(), along_hand->x()) - std::atan2(y_home.y(), y_home.x());
  } else if (g.kind == "cube") {
    const Vec3 x_obj = X_WO.rotation * Vec3::UnitX();
    const double faces = std::atan2(x_obj.y(), x_obj.x()) - std::atan2(y_home.y(), y_home.x()) + core::kPi / 2;
    yaw = faces + wrap_quarter(yaw - faces);
  }
  // Any yaw within a half turn of home (the fingers are symmetric).
  yaw = std::remainder(yaw, core::kPi);
  target_.rotation = (core::axis_angle(Vec3::UnitZ(), yaw) * home_.rotation).normalized();

  // The person reaches: wait short of the object; it is held still (offer.hold): come in.
  bool offered = competence_ == Competence::kBlind;
  for (const auto& entry : episode_->acts) {
    if (entry.value.actor == "human" && entry.value.motion && entry.value.motion->primitive &&
        entry.value.motion->primitive->value() == "offer" && seen(entry.name + ".hold")) {
      offered = true;
    }
  }
  const Vec3 toward = Vec3(grasp.x(), grasp.y(), 0).normalized();
  const Vec3 above = grasp + Vec3(0, 0, kTakeAbove);
  if (!in_skill<TakePhase>()) set_phase(TakePhase::kApproach, world.time);
  // Not yet closing on it: wait, come over it, come down to it.
  const bool before_close = in_phase(TakePhase::kApproach) || in_phase(TakePhase::kDescend);
  const double elapsed = world.time - phase_start_;
  // Both fingers on it: the person may let go any moment (after 0.2 s), so close now.
  const bool touching = robot_grasps(step.object);
  // A head leaning in over the object: back off toward the base (not with the object between
  // the fingers: the grip is finished first).
  const Vec3 head = world.joints[static_cast<size_t>(human::index(human::Joint::kHead))];
  const auto head_distance = [&](const Vec3& at) {
    double d = 1e9;
    for (const double up : {0.06, 0.16, 0.26}) d = std::min(d, (at + Vec3(0, 0, up) - head).norm());
    return d;
  };
  // (Not while the grasp point is farther from the head: coming down to an object held low
  // under a head leaning in moves the housing away from it.)
  // While the person reaches, the oracle waits short of where the object will be held (the
  // offer's zone, the object beside the palm at its height), not of the object on its way up
  // and over: a tall person leaning in to a low zone sweeps the head through the space over it.
  Vec3 wait = above - kTakeStandoff * toward;
  for (const auto& entry : episode_->acts) {
    if (competence_ != Competence::kOracle || offered || entry.value.actor != "human" || !entry.value.motion ||
        !entry.value.motion->primitive || entry.value.motion->primitive->value() != "offer") {
      continue;
    }
    const auto zone = zone_centre(entry.value);
    if (!zone || zone->head<2>().norm() < 1e-3) continue;
    const Vec3 held = *zone + Vec3(0, 0, grasp_height(g.kind, g.half_extents) - g.half_extents.z() + kTakeAbove);
    wait = held - kTakeStandoff * Vec3(zone->x(), zone->y(), 0).normalized();
  }
  const Vec3 next = step.kind == StepKind::kApproach ? wait : grasp;
  // The oracle keeps its hand and wrist clear of the head of a person leaning in (head_gap):
  // kTakeHeadGap while it waits for the person to hold the object still (they lean in at up to
  // 1.7 m/s, tall people with the head over the table beyond their hand), kTakeHeadGapTaking
  // once it comes in for the take (the head then held still, often within 0.1 m of the wrist
  // over the object). Closer, it backs off away from the head (never up; toward its base),
  // fast; otherwise it holds where it is while going on would bring them closer than that,
  // until the grip closes.
  if (competence_ == Competence::kOracle && before_close) {
    const double head_radius = kTakeHeadRadius * body_.scale;
    const double clearance = step.kind == StepKind::kApproach ? kTakeHeadGap : kTakeHeadGapTaking;
    Vec3 away;
    const double gap = head_gap(world.X_WT, head, head_radius, away);
    if (step.kind == StepKind::kApproach && offered) internal_done_[current_] = 1;
    if (gap < clearance) {
      if (in_phase(TakePhase::kDescend)) set_phase(TakePhase::kApproach, world.time);
      Vec3 dir = away;
      dir.z() = std::min(dir.z(), 0.0);
      if (tcp.z() < kTableZ + kTakeLowest) dir.z() = 0;
      const double in = dir.dot(toward);
      if (in > 0) dir -= in * toward;
      dir = dir.norm() > 0.1 ? Vec3(dir.normalized()) : Vec3(-toward);
      gripper_ = 1.0;
      speed_ = kYieldSpeed;
      target_.translation = tcp + 0.10 * dir;
      return true;
    }
    const Vec3 going = in_phase(TakePhase::kDescend) ? grasp : step.kind == StepKind::kApproach ? next : above;
    if ((going - tcp).norm() > 1e-3) {
      Pose ahead = world.X_WT;
      ahead.translation = tcp + 0.02 * (going - tcp).normalized();
      Vec3 unused;
      const double gap_ahead = head_gap(ahead, head, head_radius, unused);
      if (gap_ahead < gap && gap_ahead < clearance + (step.kind == StepKind::kApproach ? kTakeHeadResume : 0.0)) {
        gripper_ = 1.0;
        speed_ = 0;
        target_.translation = tcp;
        return true;
      }
    }
  }
  if (head_distance(tcp) < kTakeHeadClearance && head_distance(next) < head_distance(tcp) + 0.03 && before_close) {
    if (in_phase(TakePhase::kDescend)) set_phase(TakePhase::kApproach, world.time);
    gripper_ = 1.0;
    speed_ = kMaxSpeed;
    target_.translation = tcp - 0.10 * toward;
    return true;
  }
  switch (std::get<TakePhase>(phase_)) {
    case TakePhase::kApproach:  // approach: short of the object while the person reaches; take: over the grasp point
      gripper_ = 1.0;
      speed_ = kMaxSpeed;
      if (step.kind == StepKind::kApproach) {
        target_.translation = wait;
        if (offered) internal_done_[current_] = 1;  // the take comes in from here
        break;
      }
      target_.translation = above;
      if ((tcp - above).norm() < 3 * kReachedDistance && world.width > 0.07) set_phase(TakePhase::kDescend, world.time);
      break;
    case TakePhase::kDescend: {  // down to the grasp point, open
      gripper_ = 1.0;
      speed_ = kFineSpeed * 1.5;
      target_.translation = grasp;
      // Not down past the object's top with a finger over it: the fingers open only a few
      // millimetres wider than a cup, and a finger landing on its rim pushed it down in the
      // hand (a spring), the grasp point and the gripper after it, onto the hand. Over the top
      // until centred along the finger axis (the reference overshoots the corner by a
      // centimetre when the descent begins on the way in).
      Vec3 finger_axis = world.X_WT.rotation * Vec3::UnitY();
      finger_axis.z() = 0;
      const double top = (X_WO * Vec3(0, 0, 2 * g.half_extents.z())).z();
      const double slack = 0.5 * (world.width - grip_width(g.kind, g.half_extents)) - kTakeAlignMargin;
      if (finger_axis.norm() > 1e-3 && std::abs((grasp - tcp).dot(finger_axis.normalized())) > std::max(slack, 0.001) &&
          tcp.z() - kTakeFingertipsBelowTcp > top) {
        target_.translation.z() = std::max(grasp.z(), top + kTakeFingertipsBelowTcp + kTakeRimClearance);
      }
      if ((tcp - grasp).norm() < kReachedDistance || (elapsed > 2.0 && (tcp - grasp).norm() < 0.02)) {
        set_phase(TakePhase::kSqueeze, world.time);
      }
      if (touching) set_phase(TakePhase::kGrip, world.time);  // wedged on the way down: grip there
      break;
    }
    case TakePhase::kSqueeze: {  // pre-shape just wider than the object, then squeeze slowly until both fingers touch
      // (the grasp ends the take act; the gripper must not be moving then, as the place may
      // start only once the person has let go)
      const double w = grip_width(g.kind, g.half_extents);
      const double command = w + kPreshapeGap - kSqueezeRate * std::max(0.0, elapsed - kPreshapeTime);
      gripper_ = std::clamp(command / skill_robot().gripper.max_width(), 0.0, 1.0);
      speed_ = 0;
      target_.translation = grasp;
      if (touching || command < w - kSqueezeDepth) set_phase(TakePhase::kGrip, world.time);
      break;
    }
    case TakePhase::kGrip:  // full grip force, then check that something is between the fingers
      gripper_ = 0.0;
      speed_ = 0;
      target_.translation = tcp;
      if (elapsed > kCloseTime) {
        if (world.width > kHoldingWidth) {
          set_phase(TakePhase::kHold, world.time);
          internal_done_[current_] = 1;
        } else {
          set_phase(TakePhase::kApproach, world.time);  // missed: open and come in again
        }
      }
      break;
    case TakePhase::kHold:  // holding, still, until the person lets go
    case TakePhase::kBackAway:  // (the place step's)
      gripper_ = 0.0;
      speed_ = 0;
      break;
  }
  return true;
}

// TakePhase::kBackAway: the object just taken from the hand, the person still close: first
// back toward the robot's base (and a little lower), away from the person, then the place
// (PlacePhase::kCarry).
bool ExpertPolicy::run_take_retreat(const World& world) {
  const Vec3 tcp = world.X_WT.translation;
  // (Only when the step begins holding it: a place step that must pick it first picks.)
  if (in_phase(PickPhase::kApproach) && gripper_ < 0.5 && world.width > kHoldingWidth) {
    set_phase(TakePhase::kBackAway, world.time);
    retreat_from_ = tcp;
  }
  if (!in_phase(TakePhase::kBackAway)) return false;
  const Vec3 toward = Vec3(retreat_from_.x(), retreat_from_.y(), 0).normalized();
  const Vec3 back = retreat_from_ - kTakeRetreat * toward - Vec3(0, 0, 0.03);
  gripper_ = 0.0;
  speed_ = kFineSpeed * 2;
  target_.translation = back;
  if ((tcp - back).norm() < 2 * kReachedDistance || world.time - phase_start_ > 3.0) {
    set_phase(PlacePhase::kCarry, world.time);
    return false;
  }
  return true;
}

namespace {
// Offer: the estimated surface gap (m) between the robot's hand housing and wrist (a capsule of
// kOfferWristRadius along the tool axis `up` from kOfferWristFrom to kOfferWristTo over the
// TCP) and a person's head (the body model's capsule on the neck-head line, its radius times
// the body's scale).
double offer_head_gap(const Vec3& tcp, const Vec3& up, const Vec3& neck, const Vec3& head, double scale) {
  const Vec3 a = neck + kOfferHeadFrom * (head - neck);
  const Vec3 b = neck + kOfferHeadTo * (head - neck);
  double d = 1e9;
  Vec3 unused;
  for (int i = 0; i <= 10; ++i) {
    const double h = kOfferWristFrom + (kOfferWristTo - kOfferWristFrom) * i / 10.0;
    d = std::min(d, segment_distance(tcp + h * up, a, b, unused));
  }
  return d - kOfferWristRadius - kOfferHeadRadius * scale;
}
// The number a motion parameter `name` of `act` was sampled to, or nullopt.
std::optional<double> motion_number(const script::Act& act, const std::string& name) {
  if (!act.motion) return std::nullopt;
  for (const auto& param : act.motion->params) {
    if (param.name == name && param.value.kind == script::ValueTree::Kind::kScalar) {
      return param.value.scalar.expr.number;
    }
  }
  return std::nullopt;
}
// The hand turned from R0 (fingers down) so that its wrist leans `tilt` (rad) toward the
// horizontal unit direction `lean`.
Quat offer_leaning(const Quat& R0, const Vec3& lean, double tilt) {
  return (core::axis_angle(Vec3::UnitZ().cross(lean).normalized(), tilt) * R0).normalized();
}
}  // namespace

void ExpertPolicy::run_handover(const World& world, const PlanStep& step) {
  const size_t k = index_of(objects_, step.object);
  HRIB_CHECK(k < objects_.size()) << step.object;
  const ObjectGeometry& g = objects_[k];
  const Vec3 tcp = world.X_WT.translation;
  const Vec3 centre = world.centre(k, g.half_extents);
  const int side = step.target == "human.left" ? 0 : 1;
  const auto joint = [&](human::Joint j) { return world.joints[static_cast<size_t>(human::index(j))]; };
  // A palm shown with a gesture first (I2) is aimed at along the forearm's line: the object
  // comes down deeper into it, so the hand closes on it at once (release before the pull).
  const Vec3 palm = palm_shown(side)
                        ? world.palm(side)
                        : receiving_palm(joint(side == 0 ? human::Joint::kLeftWrist : human::Joint::kRightWrist),
                                         joint(side == 0 ? human::Joint::kLeftElbow : human::Joint::kRightElbow))
                              .value_or(world.palm(side));
  if (step.kind == StepKind::kOffer) {
    const bool holding = holds(world, k);
    if (in_skill<PickPhase>()) {
      if (holding && (in_phase(PickPhase::kApproach) || in_phase(PickPhase::kLift))) {
        set_phase(OfferPhase::kBring, world.time);
      } else {
        run_pick(world, step.object, true);
        internal_done_[current_] = 0;
        return;
      }
    }
    gripper_ = 0.0;
    Vec3 into = palm + (tcp - centre) + Vec3(0, 0, 0.02);
    // The oracle keeps its wrist clear of a head leaning in over the palm (a person reaching far
    // leans the trunk forward, the face over the hand): the wrist leans away from the head, as
    // little as keeps kOfferHeadGap at the TCP and at the goal (toward the robot's base first,
    // then turned up to a quarter turn either way), else as far as clears it most.
    const auto keep_wrist_from_head = [&] {
      if (competence_ != Competence::kOracle) return;
      const Vec3 neck = joint(human::Joint::kNeck);
      const Vec3 head = joint(human::Joint::kHead);
      const Vec3 goal = target_.translation;
      // (R0: the hand as the skill holds it, its axis as at home.)
      const Vec3 down = home_.rotation * Vec3::UnitZ();
      const Quat R0 = (Quat::FromTwoVectors(target_.rotation * Vec3::UnitZ(), down) * target_.rotation).normalized();
      const Vec3 base = -Vec3(goal.x(), goal.y(), 0).normalized();
      const auto gap_with = [&](const Quat& R) {
        const Vec3 up = R * Vec3(0, 0, -1);
        return std::min(offer_head_gap(tcp, up, neck, head, body_.scale), offer_head_gap(goal, up, neck, head, body_.scale));
      };
      Quat best = R0;
      double best_gap = gap_with(R0);
      double best_tilt = 0;
      for (double tilt = kOfferTiltStep; best_gap < kOfferHeadGap && tilt <= kOfferMaxTilt + 1e-9;
           tilt += kOfferTiltStep) {
        for (const double turn : {0.0, core::kPi / 4, -core::kPi / 4, core::kPi / 2, -core::kPi / 2}) {
          const Quat R = offer_leaning(R0, core::axis_angle(Vec3::UnitZ(), turn) * base, tilt);
          const double gap = gap_with(R);
          if (gap > best_gap + 1e-6) {
            best = R;
            best_gap = gap;
            best_tilt = tilt;
          }
          if (best_gap >= kOfferHeadGap) break;
        }
      }
      if (best_tilt > 0 || (target_.rotation * Vec3::UnitZ() - down).norm() > 1e-9) target_.rotation = best;
    };
    // Until the receiving hand is held out (receive.present): toward a palm the person shows with a gesture
    // (give_me), stopping short of it on the robot's side; otherwise (a hand still reaching
    // out, through where the robot would wait) in front of the robot. Then over the palm and
    // down into it.
    const std::string receiver = receiving_act(step.object);
    if (!receiver.empty() && !seen(receiver + ".present") && competence_ != Competence::kBlind) {
      speed_ = kMaxSpeed;
      const Vec3 toward = Vec3(palm.x(), palm.y(), 0).normalized();
      target_.translation = palm_shown(side) ? Vec3(into + Vec3(0, 0, kOfferAbove) - kOfferStandoff * toward)
                                             : Vec3(0.40, std::clamp(tcp.y(), -0.2, 0.2), 1.0);
      if (palm_shown(side)) target_.translation = rise_first(tcp, target_.translation);
      keep_wrist_from_head();
      return;
    }
    // The baselines do not re-plan: they bring it where they first saw the hand held out, also
    // when the hand then moves (receive's shift_by); the oracle follows the live palm.
    if (competence_ != Competence::kOracle && !latched_palm_valid_) {
      latched_palm_ = palm;
      latched_palm_valid_ = true;
    }
    const Vec3 aimed = competence_ == Competence::kOracle ? palm : latched_palm_;
    into = aimed + (tcp - centre) + Vec3(0, 0, 0.02);
    if (!receiver.empty() && palm_turned_in(receiver)) {
      into.z() = std::max(into.z(), aimed.z() + kMedialPalmClearance);
    }
    // A palm shown with a gesture: the object's centre kCentreOverPalm over the palm's centre
    // (the hand closes on an object within 0.06 m of it), the fingertips at most
    // kFingertipsIntoHand into the hand, above any other object standing under the palm, and
    // the last of the way down slowly: the hand closes on the way and the release holds still
    // there. (Aimed deeper along the forearm's line, the fingers were pressed onto the hand,
    // whose friction held them shut when they opened to let go, until the person pulled.)
    bool into_shown_palm = false;
    if (palm_shown(side) && competence_ == Competence::kOracle) {
      const Vec3 wrist = joint(side == 0 ? human::Joint::kLeftWrist : human::Joint::kRightWrist);
      auto centre_of_palm =
          shown_palm(wrist, joint(side == 0 ? human::Joint::kLeftShoulder : human::Joint::kRightShoulder), body_.palm_distance);
      // (The receive act's zone, where the person brings the palm, once the wrist is there.)
      for (const auto& entry : episode_->acts) {
        if (entry.name != receiver) continue;
        const auto zone = zone_centre(entry.value);
        if (zone && (*zone - wrist).norm() < body_.palm_distance + 0.03) centre_of_palm = zone;
      }
      if (centre_of_palm) {
        into_shown_palm = true;
        into = *centre_of_palm + Vec3(0, 0, kCentreOverPalm) + (tcp - centre);
        into.z() = std::max(into.z(), centre_of_palm->z() + kHandRadius * body_.scale + kFingertipsBelowTcp -
                                          kFingertipsIntoHand);
        const Vec3 bottom = into - (tcp - world.objects[k].translation);
        for (size_t i = 0; i < objects_.size(); ++i) {
          const Vec3& half = objects_[i].half_extents;
          const double reach = std::max(half.x(), half.y()) + std::max(g.half_extents.x(), g.half_extents.y()) + 0.01;
          if (i == k || (world.objects[i].translation - bottom).head<2>().norm() > reach) continue;
          into.z() = std::max(into.z(), world.objects[i].translation.z() + 2 * half.z() + 0.01 + tcp.z() -
                                            world.objects[k].translation.z());
        }
      }
    }
    // Over the palm first, then down into it (the hand housing stays clear of the fingers); a
    // hand held out without a gesture: within a cone over it (twice as high as it is off to the
    // side), so a palm at the edge of the robot's reach is still come down to (a tall object
    // held at its neck over a high palm).
    speed_ = kFineSpeed * 2;
    const Vec3 over = into + Vec3(0, 0, kOfferAbove);
    const double off = (tcp - into).head<2>().norm();
    target_.translation = palm_shown(side) ? (off > 0.03 ? over : into)
                                           : Vec3(into + Vec3(0, 0, std::min(kOfferAbove, 2 * off)));
    if (into_shown_palm && off <= 0.03 && tcp.z() < into.z() + 0.06) speed_ = kFineSpeed * 0.5;
    // Low and far from the palm (just picked): up first, not through the reaching arm.
    if (!palm_shown(side) && tcp.z() < into.z() && (tcp - into).head<2>().norm() > 0.10) {
      target_.translation = Vec3(tcp.x(), tcp.y(), over.z());
    }
    if (palm_shown(side)) target_.translation = rise_first(tcp, target_.translation);
    // The oracle brings the object into a hand held out without a gesture only once the hand
    // has been open for the receive act's `open` time (OfferPhase::kHandOpen from when it opened): the person
    // closes it no earlier, and an object still coming in when it counts as delivered starts
    // the let-go before the grasp. Until then it stays kOfferHoverAbove over the palm.
    if (!palm_shown(side) && !receiver.empty() && competence_ == Competence::kOracle) {
      if (in_phase(OfferPhase::kBring) && seen(receiver + ".open")) set_phase(OfferPhase::kHandOpen, world.time);
      double open = 0;
      for (const auto& entry : episode_->acts) {
        if (entry.name == receiver) open = motion_number(entry.value, "open").value_or(0);
      }
      if (in_phase(OfferPhase::kBring) || world.time - phase_start_ < open) {
        target_.translation.z() = std::max(target_.translation.z(), into.z() + kOfferHoverAbove);
      }
    }
    keep_wrist_from_head();
    // Done once the object is in the palm (not when the act's looser goal distance first holds:
    // the person closes the hand only when the object is inside the palm region), or once the
    // hand closes on it.
    if ((tcp - into).norm() < kReachedDistance || human_holds(step.object) ||
        (!receiver.empty() && seen(receiver + ".close"))) {
      internal_done_[current_] = 1;
    }
    return;
  }
  // Release once the hand holds it (blind: at once), then withdraw.
  if (!in_skill<ReleasePhase>()) set_phase(ReleasePhase::kWaitForHand, world.time);
  // Until the fingers are open: where the hand is, no farther (the last of the descent into the
  // palm would press the fingers onto the person's hand, whose friction then holds them shut).
  if (!in_phase(ReleasePhase::kWithdraw)) target_.translation = tcp;
  if (in_phase(ReleasePhase::kWaitForHand)) {
    gripper_ = 0.0;
    speed_ = kFineSpeed;
    // Blind does not watch the hand: it lets go as soon as the step begins.
    if (competence_ == Competence::kBlind || human_holds(step.object)) {
      set_phase(ReleasePhase::kOpen, world.time);
    }
    return;
  }
  const double elapsed = world.time - phase_start_;
  // The oracle draws its fingers out of the hand as soon as they are open clear of the object
  // (the person may pull the hand back at once), up as much as back.
  const bool oracle = competence_ == Competence::kOracle;
  if (in_phase(ReleasePhase::kOpen)) {
    gripper_ = 1.0;
    speed_ = kFineSpeed;
    const bool clear = oracle && elapsed > kOfferOpenAtLeast &&
                       world.width > grip_width(objects_[k].kind, objects_[k].half_extents) + kOfferFingersClear;
    if (elapsed > kOpenTime || clear) set_phase(ReleasePhase::kWithdraw, world.time);
  } else {
    gripper_ = 1.0;
    speed_ = kFineSpeed * 2;
    target_.translation = oracle ? Vec3(tcp + kOfferWithdraw * Vec3(-1, 0, 1).normalized())
                                 : Vec3(tcp.x() - 0.15, tcp.y(), tcp.z() + 0.05);
    if (elapsed > 1.0) internal_done_[current_] = 1;
  }
}

bool ExpertPolicy::robot_grasps(const std::string& object) const {
  const int k = static_cast<int>(index_of(objects_, object));
  return std::any_of(predicates_.begin(), predicates_.end(), [&](const LoggedPredicate& p) {
    return p.value && p.holding && p.holding->robot_grasps(k);
  });
}

bool ExpertPolicy::human_holds(const std::string& object) const {
  const int k = static_cast<int>(index_of(objects_, object));
  return std::any_of(predicates_.begin(), predicates_.end(), [&](const LoggedPredicate& p) {
    return p.value && p.holding && p.holding->human_holds(k);
  });
}

namespace {
// The hand parameter of a human act with one of `primitives` ("" otherwise).
std::string hand_of(const script::Act& act, std::initializer_list<const char*> primitives) {
  if (act.actor != "human" || !act.motion || !act.motion->primitive) return "";
  const std::string primitive = act.motion->primitive->value();
  if (std::none_of(primitives.begin(), primitives.end(), [&](const char* p) { return primitive == p; })) return "";
  for (const auto& param : act.motion->params) {
    const script::Expr& e = param.value.scalar.expr;
    if (param.name == "hand" && e.kind == script::Expr::Kind::kString) return e.text;
  }
  return "";
}
}  // namespace

bool ExpertPolicy::palm_shown(int side) const {
  for (const auto& entry : episode_->acts) {
    if (hand_of(entry.value, {"give_me"}) == (side == 0 ? "left" : "right") && seen(entry.name + ".gesture")) return true;
  }
  return false;
}

bool ExpertPolicy::receiving_hand(int side) const {
  for (const auto& entry : episode_->acts) {
    if (hand_of(entry.value, {"give_me", "receive"}) != (side == 0 ? "left" : "right")) continue;
    if (seen(entry.name + ".start") && !seen(entry.name + ".end")) return true;
  }
  return false;
}

bool ExpertPolicy::palm_turned_in(const std::string& act) const {
  for (const auto& entry : episode_->acts) {
    if (entry.name != act || !entry.value.motion) continue;
    for (const auto& param : entry.value.motion->params) {
      const script::Expr& e = param.value.scalar.expr;
      if (param.name == "palm" && e.kind == script::Expr::Kind::kString) return e.text == "medial";
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

}  // namespace hribench::policy
