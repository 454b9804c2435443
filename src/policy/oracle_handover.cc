// The expert's handover skills: offer an object into a human palm, release once the hand holds it.
#include "policy/oracle.h"

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "policy/oracle_internal.h"

namespace hribench::policy {

using namespace oracle_internal;  // NOLINT: the expert's own internals

namespace {
// Offering: the object comes down into the palm from this high above it (m), and waits this far
// short of a shown palm (horizontally, toward the robot) until the hand opens.
constexpr double kOfferAbove = 0.10;
constexpr double kOfferStandoff = 0.12;
}  // namespace

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
    const Vec3 into = palm + (tcp - centre) + Vec3(0, 0, 0.02);
    // Until the receiving hand is open: toward the palm the person shows, stopping short of it
    // on the robot's side; a hand that is not shown yet (hanging) is waited for in front of
    // the robot. Then over the palm and down into it.
    const std::string receiver = receiving_act(step.object);
    if (!receiver.empty() && !seen(receiver + ".open") && competence_ != Competence::kBlind) {
      speed_ = kMaxSpeed;
      const Vec3 toward = Vec3(palm.x(), palm.y(), 0).normalized();
      target_.translation = palm.z() > kTableZ + 0.12 ? Vec3(into + Vec3(0, 0, kOfferAbove) - kOfferStandoff * toward)
                                                      : Vec3(0.40, std::clamp(tcp.y(), -0.2, 0.2), 1.0);
      return;
    }
    // Over the palm first, then down into it (the hand housing stays clear of the fingers).
    speed_ = kFineSpeed * 2;
    target_.translation = (tcp - into).head<2>().norm() > 0.03 ? Vec3(into + Vec3(0, 0, kOfferAbove)) : into;
    // Done once the object is in the palm (not when the act's looser goal distance first holds:
    // the person closes the hand only when the object is inside the palm region), or once the
    // hand closes on it.
    if ((tcp - into).norm() < kReachedDistance || human_holds(step.object) ||
        (!receiver.empty() && seen(receiver + ".close"))) {
      internal_done_[current_] = 1;
    }
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

bool ExpertPolicy::receiving_hand(int side) const {
  for (const auto& entry : episode_->acts) {
    const script::Act& act = entry.value;
    if (act.actor != "human" || !act.motion || !act.motion->primitive) continue;
    const std::string primitive = act.motion->primitive->value();
    if (primitive != "give_me" && primitive != "receive") continue;
    if (!seen(entry.name + ".start") || seen(entry.name + ".end")) continue;
    for (const auto& param : act.motion->params) {
      const script::Expr& e = param.value.scalar.expr;
      if (param.name == "hand" && e.kind == script::Expr::Kind::kString &&
          e.text == (side == 0 ? "left" : "right")) {
        return true;
      }
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
