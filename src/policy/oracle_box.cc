// The expert's box retrieval (C3): wait beside the lidded box while the person opens it, reach
// in over the rim once the lid is held open, grasp the object inside by finger contact with the
// hand housing above the walls, lift it out, then leave the box with it.
#include "policy/oracle_box.h"

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "policy/oracle.h"
#include "policy/oracle_internal.h"

namespace hribench::policy {
namespace oracle_box {

using core::Pose;
using core::Vec3;

Vec3 centre(const Pose& X_WB) { return X_WB * Vec3(0, 0, kClosedHalfHeight); }

double rim_z(const Pose& X_WB) { return X_WB.translation.z() + kWallHeight; }

bool inside(const Pose& X_WB, const Vec3& p_W, double above) {
  const Vec3 q = X_WB.inverse() * p_W;
  return std::abs(q.x()) <= kHalfX && std::abs(q.y()) <= kHalfY && q.z() < kWallHeight + above;
}

double grasp_z(const Pose& X_WB, double z) {
  // The housing's lowest edge (tilted): its bottom face's edge on the robot's side.
  const double lowest = kHousingAboveTcp * std::cos(kTilt) - kHousingHalfWidth * std::sin(kTilt);
  return std::max(z, rim_z(X_WB) + kHousingClearance - lowest);
}

core::Quat hand_rotation(const Pose& X_WB, const Pose& X_home) {
  const Vec3 hinge = X_WB.rotation * Vec3::UnitY();
  return (core::axis_angle(hinge, -kTilt) * core::axis_angle(Vec3::UnitZ(), finger_yaw(X_WB, X_home)) *
          X_home.rotation).normalized();
}

Vec3 grasp_point(const Pose& X_WB, const Vec3& p_W) { return p_W - kGraspShift * (X_WB.rotation * Vec3::UnitX()); }

double entry_z(const Pose& X_WB) { return rim_z(X_WB) + kTipClearance + kTipBelowTcp; }

Vec3 wait_point(const Pose& X_WB, const Vec3& person, double near) {
  // Beside the box along its hinge (y) axis, on the side away from the person, a little toward
  // the robot, above the rim: out of the way of the lid, its handle and the arm opening it.
  const Vec3 q = X_WB.inverse() * person;
  const double side = q.y() > 0 ? -1.0 : 1.0;
  const Vec3 direction = (X_WB.rotation * Vec3(-0.10, side * 0.20, 0.14)).normalized();
  return centre(X_WB) + kWaitShare * near * direction;
}

double exit_z(const Pose& X_WB, const Vec3& tcp, double distance) {
  const double reach = distance + kLeaveMargin;
  const Vec3 c = centre(X_WB);
  const double horizontal = (tcp - c).head<2>().norm();
  const double up = std::sqrt(std::max(0.0, reach * reach - horizontal * horizontal));
  return std::max(c.z() + up, entry_z(X_WB));
}

double finger_yaw(const Pose& X_WB, const Pose& X_home) {
  const Vec3 hinge = X_WB.rotation * Vec3::UnitY();
  const Vec3 fingers = X_home.rotation * Vec3::UnitY();
  const double a = std::atan2(hinge.y(), hinge.x()) - std::atan2(fingers.y(), fingers.x());
  return a - core::kPi * std::floor((a + core::kPi / 2) / core::kPi);  // modulo pi
}

}  // namespace oracle_box

using namespace oracle_internal;  // NOLINT: the expert's own internals

size_t ExpertPolicy::box_containing(const World& world, size_t object) const {
  const Vec3 p = world.objects[object].translation + Vec3(0, 0, 0.005);
  for (size_t b = 0; b < objects_.size(); ++b) {
    if (b != object && objects_[b].kind == "box" && oracle_box::inside(world.objects[b], p, 0.05)) return b;
  }
  return objects_.size();
}

int ExpertPolicy::lid_arm(const World& world) const {
  for (const auto& entry : episode_->acts) {
    const script::Act& a = entry.value;
    const bool lid = a.actor == "human" && a.motion && a.motion->primitive &&
                     a.motion->primitive->value() == "hold_lid";
    if (!lid || !seen(entry.name + ".start") || seen(entry.name + ".end")) continue;
    // The hand at the lid: the palm nearest (horizontally) to a box.
    double best = 1e9;
    int arm = -1;
    for (size_t b = 0; b < objects_.size(); ++b) {
      if (objects_[b].kind != "box") continue;
      for (int side = 0; side < 2; ++side) {
        const double d = (world.palm(side) - world.objects[b].translation).head<2>().norm();
        if (d < best) {
          best = d;
          arm = side;
        }
      }
    }
    return arm;
  }
  return -1;
}

double ExpertPolicy::lid_arm_distance(const World& world, const std::array<Vec3, 4>& points, int side) const {
  using human::Joint;
  const auto joint = [&](Joint left, Joint right) {
    return world.joints[static_cast<size_t>(human::index(side == 0 ? left : right))];
  };
  const Vec3 shoulder = joint(Joint::kLeftShoulder, Joint::kRightShoulder);
  const Vec3 elbow = joint(Joint::kLeftElbow, Joint::kRightElbow);
  const Vec3 wrist = joint(Joint::kLeftWrist, Joint::kRightWrist);
  // The hand grips the lid's edge below the wrist (not along the forearm, as World::palm).
  const Vec3 hand = wrist - Vec3(0, 0, oracle_box::kHandLength);
  double best = 1e9;
  Vec3 closest;
  for (const Vec3& p : points) {
    best = std::min({best, segment_distance(p, shoulder, elbow, closest), segment_distance(p, elbow, wrist, closest),
                     segment_distance(p, wrist, hand, closest)});
  }
  return best;
}

bool ExpertPolicy::run_box_step(const World& world, const PlanStep& step) {
  const size_t k = index_of(objects_, step.object);
  if (k >= objects_.size()) return false;
  if (step.kind == StepKind::kApproach && objects_[k].kind == "box") {
    run_box_wait(world, k, step.distance);
    return true;
  }
  const size_t box = box_containing(world, k);
  if (step.kind != StepKind::kPick || box >= objects_.size()) return false;
  run_box_pick(world, k, box);
  return true;
}

void ExpertPolicy::run_leave(const World& world, const PlanStep& step) {
  const size_t k = index_of(objects_, step.object);
  const size_t c = index_of(objects_, step.target);
  HRIB_CHECK(k < objects_.size() && c < objects_.size()) << step.object << " " << step.target;
  const Vec3 tcp = world.X_WT.translation;
  const bool holding = holds(world, k);
  // Lost it (or not yet holding it) inside a box: take it again.
  const size_t box = box_containing(world, k);
  if (!holding && box < objects_.size()) {
    run_box_pick(world, k, box);
    internal_done_[current_] = 0;
    return;
  }
  // Straight up until the TCP is beyond the distance from the target and the object is above
  // the target's top.
  gripper_ = holding ? 0.0 : 1.0;
  speed_ = kMaxSpeed;
  // (near() measures from the target's centre.)
  const Vec3 origin = world.centre(c, objects_[c].half_extents);
  const double reach = step.distance + oracle_box::kLeaveMargin;
  const double horizontal = (tcp - origin).head<2>().norm();
  const double above_top = origin.z() + objects_[c].half_extents.z() + 0.02 + (tcp.z() - world.objects[k].translation.z());
  const double z = std::max(origin.z() + std::sqrt(std::max(0.0, reach * reach - horizontal * horizontal)), above_top);
  target_.translation = Vec3(tcp.x(), tcp.y(), z);
  if (std::abs(tcp.z() - z) < 2 * kReachedDistance) internal_done_[current_] = 1;
}

void ExpertPolicy::run_box_wait(const World& world, size_t box, double near) {
  const Pose& X_WB = world.objects[box];
  const Vec3 tcp = world.X_WT.translation;
  gripper_ = 1.0;
  target_.rotation = oracle_box::hand_rotation(X_WB, home_);
  // Once the next step may start (the lid is open), straight over the box: the approach ends
  // on the way in.
  const bool go = current_ + 1 < plan_.size() &&
                  (plan_[current_ + 1].after.empty() || seen(plan_[current_ + 1].after));
  if (go) {
    speed_ = kMaxSpeed;
    target_.translation = Vec3(X_WB.translation.x(), X_WB.translation.y(), oracle_box::entry_z(X_WB));
    return;
  }
  // Else to the waiting point: over it first (from above, outside `near`), the last few
  // centimetres crept (arriving near the box is not yet the reach into it).
  const Vec3 person = world.joints[static_cast<size_t>(human::index(human::Joint::kPelvis))];
  const Vec3 wait = oracle_box::wait_point(X_WB, person, near);
  const Vec3 outward = (wait - oracle_box::centre(X_WB)).normalized();
  const Vec3 ready = wait + oracle_box::kCreepDistance * outward;
  const Vec3 above = ready + Vec3(0, 0, 0.10);
  if (!in_phase(BoxWaitPhase::kCreep)) {  // (the step begins here)
    speed_ = kMaxSpeed;
    const bool high = tcp.z() > above.z() - 0.03;
    target_.translation = high ? ready : above;
    if (high && (tcp - ready).norm() < 2 * kReachedDistance) set_phase(BoxWaitPhase::kCreep, world.time);
    return;
  }
  speed_ = oracle_box::kCreepSpeed;
  target_.translation = wait;
}

void ExpertPolicy::run_box_pick(const World& world, size_t k, size_t box) {
  const ObjectGeometry& g = objects_[k];
  const Pose& X_WB = world.objects[box];
  // Oracle: the live pose; baselines: the pose seen when the step began.
  Vec3 origin = world.objects[k].translation;
  if (competence_ != Competence::kOracle && latched_valid_) origin = latched_;
  const Vec3 point = oracle_box::grasp_point(X_WB, origin);
  const Vec3 grasp(point.x(), point.y(),
                   oracle_box::grasp_z(X_WB, origin.z() + grasp_height(g.kind, g.half_extents)));
  const Vec3 entry(grasp.x(), grasp.y(), oracle_box::entry_z(X_WB));
  target_.rotation = oracle_box::hand_rotation(X_WB, home_);
  const Vec3 tcp = world.X_WT.translation;
  const double w = grip_width(g.kind, g.half_extents);
  const double elapsed = world.time - phase_start_;
  switch (std::get<PickPhase>(phase_)) {
    case PickPhase::kApproach: {  // open, over the rim above the grasp (rising first when low and to the side)
      gripper_ = 1.0;
      speed_ = kMaxSpeed;
      const double horizontal = (tcp - entry).head<2>().norm();
      target_.translation = horizontal > 0.02 && tcp.z() < entry.z() - 0.02 ? Vec3(tcp.x(), tcp.y(), entry.z()) : entry;
      if ((tcp - entry).norm() < 2 * kReachedDistance) set_phase(PickPhase::kDescend, world.time);
      break;
    }
    case PickPhase::kDescend:  // down into the box, the fingers pre-shaped just wider than the object
      gripper_ = std::min(1.0, (w + kPreshapeGap) / skill_robot().gripper.max_width());
      speed_ = oracle_box::kDescentSpeed;
      target_.translation = grasp;
      if ((tcp - grasp).norm() < kReachedDistance / 2 || (elapsed > 2.0 && (tcp - grasp).norm() < 2 * kReachedDistance)) {
        set_phase(PickPhase::kClose, world.time);
      }
      break;
    case PickPhase::kClose: {  // squeeze (faster than on the table: the lid window is short), check the grip
      const Grip grip = squeeze(world, w, grasp, 0.0, oracle_box::kSqueezeRate, oracle_box::kGripTime);
      if (grip == Grip::kHolding) set_phase(PickPhase::kLift, world.time);
      if (grip == Grip::kMissed) set_phase(PickPhase::kApproach, world.time);
      break;
    }
    case PickPhase::kLift: {  // lift until the object is over the rim
      gripper_ = 0.0;
      speed_ = kMaxSpeed;
      const double z = oracle_box::rim_z(X_WB) + 0.02 + (tcp.z() - world.objects[k].translation.z());
      target_.translation = Vec3(tcp.x(), tcp.y(), std::max(z, oracle_box::entry_z(X_WB)));
      if (std::abs(tcp.z() - target_.translation.z()) < 2 * kReachedDistance) internal_done_[current_] = 1;
      break;
    }
  }
}

}  // namespace hribench::policy
