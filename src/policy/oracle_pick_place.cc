// The expert's pick-and-place skills: top-down grasp by finger contact, carry, place in or on a
// target, put back, go home.
#include "policy/oracle.h"

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "policy/oracle_internal.h"

namespace hribench::policy {

using namespace oracle_internal;  // NOLINT: the expert's own internals

void ExpertPolicy::run_pick(const World& world, const std::string& object, bool close) {
  const size_t k = index_of(objects_, object);
  HRIB_CHECK(k < objects_.size()) << object;
  const ObjectGeometry& g = objects_[k];
  // Oracle: the live pose; baselines: the pose seen when the step began.
  Pose X_WO = world.objects[k];
  if (competence_ != Competence::kOracle && latched_valid_) X_WO.translation = latched_;
  // Recovery: a knocked-over bottle or cup is grasped across its lying body.
  const bool on_side = lying(g.kind, X_WO);
  const Vec3 grasp = on_side ? lying_grasp(X_WO, g.half_extents)
                             : Vec3(X_WO.translation + Vec3(0, 0, grasp_height(g.kind, g.half_extents)));
  // Finger axis across the cube's faces (cylinders: any; lying: across the axis).
  double yaw = 0;
  if (on_side) {
    const Vec3 axis = X_WO.rotation * Vec3::UnitZ();
    const Vec3 y_home = home_.rotation * Vec3::UnitY();
    yaw = wrap_half_turn(std::atan2(axis.y(), axis.x()) - std::atan2(y_home.y(), y_home.x()) + core::kPi / 2);
  } else if (g.kind == "cube" || g.kind == "plank") {
    const Vec3 x_obj = X_WO.rotation * Vec3::UnitX();
    const Vec3 y_home = home_.rotation * Vec3::UnitY();
    yaw = wrap_quarter(std::atan2(x_obj.y(), x_obj.x()) - std::atan2(y_home.y(), y_home.x()) +
                       core::kPi / 2);
  }
  // Recovery: of a cube's two finger axes, the one that keeps the hand housing (0.1 m each side
  // of the TCP along the finger axis, 0.044 m above it) clear of the objects beside it that
  // stand taller than the housing's bottom (bins' walls, bottles), each a disc of its largest
  // half extent.
  if (g.kind == "cube" && !on_side) {
    const auto clearance = [&](double turn) {
      const Vec3 across = core::axis_angle(Vec3::UnitZ(), turn) * home_.rotation * Vec3::UnitY();
      const Vec3 a(grasp.x() - kHousingHalfLength * across.x(), grasp.y() - kHousingHalfLength * across.y(), 0);
      const Vec3 b(grasp.x() + kHousingHalfLength * across.x(), grasp.y() + kHousingHalfLength * across.y(), 0);
      double clear = 1e9;
      for (size_t i = 0; i < objects_.size(); ++i) {
        const Vec3& h = objects_[i].half_extents;
        if (i == k || world.objects[i].translation.z() + 2 * h.z() < grasp.z() + kHousingAboveTcp) continue;
        Vec3 closest;
        const Vec3 c(world.objects[i].translation.x(), world.objects[i].translation.y(), 0);
        clear = std::min(clear, segment_distance(c, a, b, closest) - std::max(h.x(), h.y()));
      }
      return clear;
    };
    const double other = yaw >= 0 ? yaw - core::kPi / 2 : yaw + core::kPi / 2;
    const double clear = clearance(yaw);
    if (clear < kHousingClearanceWanted && clearance(other) > clear) yaw = other;
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
  switch (std::get<PickPhase>(phase_)) {
    case PickPhase::kApproach: {  // open, go above the grasp (rising first when low and far)
      gripper_ = 1.0;
      speed_ = kMaxSpeed;
      const Vec3 above(grasp.x(), grasp.y(), above_z);
      const double horizontal = (tcp - above).head<2>().norm();
      target_.translation = horizontal > 0.03 && tcp.z() < above_z - 0.03
                                ? Vec3(tcp.x(), tcp.y(), above_z)
                                : above;
      if ((tcp - above).norm() < 2 * kReachedDistance && world.width > 0.07) {
        set_phase(PickPhase::kDescend, world.time);
      }
      break;
    }
    case PickPhase::kDescend:  // descend onto the grasp
      gripper_ = 1.0;
      speed_ = kFineSpeed * 1.5;
      target_.translation = grasp;
      if ((tcp - grasp).norm() < kReachedDistance / 2 ||
          (elapsed > 3.0 && (tcp - grasp).norm() < 2 * kReachedDistance)) {
        if (close) set_phase(PickPhase::kClose, world.time);
      }
      break;
    case PickPhase::kClose: {  // close on the object, then check that something is between the fingers
      // Pre-shape just wider than the object, then squeeze: the fingers touch it slowly (the
      // grasp, which ends an act, is not in the middle of a fast gripper motion).
      const Grip grip = squeeze(world, on_side ? 2 * g.half_extents.x() : grip_width(g.kind, g.half_extents), grasp,
                                kPreshapeTime, kSqueezeRate, kCloseTime);
      if (grip == Grip::kHolding) set_phase(PickPhase::kLift, world.time);
      if (grip == Grip::kMissed) set_phase(PickPhase::kApproach, world.time);
      break;
    }
    case PickPhase::kLift: {  // lift clear
      gripper_ = 0.0;
      speed_ = kMaxSpeed * 0.6;
      target_.translation = Vec3(grasp.x(), grasp.y(), above_z + 0.05);
      if ((tcp - target_.translation).norm() < 2 * kReachedDistance) internal_done_[current_] = 1;
      break;
    }
  }
}

ExpertPolicy::Grip ExpertPolicy::squeeze(const World& world, double width, const Vec3& grasp, double preshape,
                                         double rate, double grip) {
  const double elapsed = world.time - phase_start_;
  const double command = width + kPreshapeGap - rate * std::max(0.0, elapsed - preshape);
  gripper_ = command > width - kSqueezeDepth ? std::min(1.0, command / skill_robot().gripper.max_width()) : 0.0;
  speed_ = 0;
  target_.translation = grasp;
  if (elapsed <= preshape + (kPreshapeGap + kSqueezeDepth) / rate + grip) return Grip::kClosing;
  return world.width > kHoldingWidth ? Grip::kHolding : Grip::kMissed;
}

bool ExpertPolicy::holds(const World& world, size_t k) const {
  const Vec3 centre = world.centre(k, objects_[k].half_extents);
  return gripper_ < 0.5 && world.width > kHoldingWidth &&
         (centre - world.X_WT.translation).norm() < 0.06 + objects_[k].half_extents.z();
}

void ExpertPolicy::run_place(const World& world, const PlanStep& step) {
  const size_t k = index_of(objects_, step.object);
  HRIB_CHECK(k < objects_.size()) << step.object;
  const Vec3 tcp = world.X_WT.translation;
  const bool holding = holds(world, k);
  // Not holding it yet (or lost it before the release): pick it first.
  if (in_skill<PickPhase>()) {
    if (holding && (in_phase(PickPhase::kApproach) || in_phase(PickPhase::kLift))) {  // already holding it, or lifting it
      set_phase(PlacePhase::kCarry, world.time);
    } else {
      run_pick(world, step.object, true);
      internal_done_[current_] = 0;
      if (in_phase(PickPhase::kLift) && holding) set_phase(PlacePhase::kCarry, world.time);
      return;
    }
  }
  const PlacePhase phase = std::get<PlacePhase>(phase_);
  if ((phase == PlacePhase::kCarry || phase == PlacePhase::kLower) && !holding) {
    set_phase(PickPhase::kApproach, world.time);
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
    if (phase == PlacePhase::kCarry && (!spot_valid_ || world.time == phase_start_)) {
      Pose X_WC = world.objects[c];
      X_WC.translation = origin;
      spot_ = free_spot(world, k, c, X_WC);
      spot_valid_ = true;
    }
    place_xy = spot_valid_ ? spot_ : origin;
    if (is_container(cg.kind)) {
      container_top = origin.z() + 2 * cg.half_extents.z();
      surface = origin.z() + 0.008;
      // Released just above the floor: a cup dropped 1.5 cm onto a tray's thin floor rocks on
      // its rim (MuJoCo's cylinder-box contact) and pushes the tray.
      gap = 0.005;
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
  // Recovery: a lying object's bottom is under the middle of its axis; carried into a container
  // with its axis along the container's length.
  const bool on_side = lying(objects_[k].kind, world.objects[k]);
  const Vec3 bottom = on_side ? Vec3(lying_grasp(world.objects[k], objects_[k].half_extents) -
                                     Vec3(0, 0, objects_[k].half_extents.x()))
                              : world.objects[k].translation;
  if (on_side && container_top > 0 && (phase == PlacePhase::kCarry || phase == PlacePhase::kLower)) {
    const Vec3 axis = world.objects[k].rotation * Vec3::UnitZ();
    const Vec3 length = world.objects[index_of(objects_, step.target)].rotation * Vec3::UnitX();
    const double turn = wrap_half_turn(std::atan2(length.y(), length.x()) - std::atan2(axis.y(), axis.x()));
    target_.rotation = (core::axis_angle(Vec3::UnitZ(), turn) * world.X_WT.rotation).normalized();
  }
  const Vec3 offset = tcp - bottom;  // TCP above the object's bottom
  double top = kTableZ;
  for (size_t i = 0; i < objects_.size(); ++i) {
    if (i != k) top = std::max(top, world.objects[i].translation.z() + 2 * objects_[i].half_extents.z());
  }
  const double carry_z = top + kCarryClearance + offset.z();
  const Vec3 over(place_xy.x() + offset.x(), place_xy.y() + offset.y(), carry_z);
  const double elapsed = world.time - phase_start_;
  switch (phase) {
    case PlacePhase::kCarry: {  // carry over the target (rising first when low and far)
      gripper_ = 0.0;
      speed_ = kMaxSpeed;
      const double horizontal = (tcp - over).head<2>().norm();
      target_.translation = horizontal > 0.03 && tcp.z() < carry_z - 0.03
                                ? Vec3(tcp.x(), tcp.y(), carry_z)
                                : over;
      if ((tcp - over).norm() < 2 * kReachedDistance) set_phase(PlacePhase::kLower, world.time);
      break;
    }
    case PlacePhase::kLower: {  // lower onto the surface
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
      // Recovery: the time-out (an object resting on something short of `down`) does not count
      // while a separation stop holds the robot more than 3 cm above `down` (no release from
      // a height).
      if (ssm_stopped_ && (tcp - down).norm() > 0.03) phase_start_ += world.dt;
      if ((tcp - down).norm() < kReachedDistance / 2 || elapsed > 4.0) set_phase(PlacePhase::kRelease, world.time);
      break;
    }
    case PlacePhase::kRelease:
      gripper_ = 1.0;
      speed_ = 0;
      if (elapsed > kOpenTime) set_phase(PlacePhase::kWithdraw, world.time);
      break;
    case PlacePhase::kWithdraw: {  // upward
      gripper_ = 1.0;
      speed_ = kMaxSpeed * 0.5;
      target_.translation = Vec3(tcp.x(), tcp.y(), std::max(tcp.z(), top + 0.10));
      if (elapsed > 0.8) {
        const bool ended = plan_[current_].act.empty() || seen(plan_[current_].act + ".end");
        if (ended || competence_ != Competence::kOracle) {
          internal_done_[current_] = 1;
        } else {
          set_phase(PickPhase::kApproach, world.time);  // the goal does not hold: again from the live poses
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

}  // namespace hribench::policy
