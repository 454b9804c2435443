#include "policy/oracle_plan.h"

#include <algorithm>
#include <optional>
#include <string_view>

#include "core/errors.h"
#include "script/predicate.h"

namespace hribench::policy {
namespace {

using script::Arg;
using script::Atom;
using script::Predicate;

// The act name of an event "ACT.PHASE".
std::string act_of_event(const std::string& event) { return event.substr(0, event.find('.')); }

const script::Act* find_act(const script::EpisodeSpec& episode, const std::string& name) {
  for (const auto& entry : episode.acts) {
    if (entry.name == name) return &entry.value;
  }
  return nullptr;
}

std::string hand_name(const Arg& arg) {
  if (arg.kind == Arg::Kind::kHand) return arg.index == script::kLeftHand ? "human.left" : "human.right";
  return "human.any";
}

// The positive and negated atoms of a conjunction.
void flatten(const Predicate& p, bool negated, std::vector<std::pair<const Predicate*, bool>>& out) {
  if (p.atom == Atom::kAnd && !negated) {
    for (const Predicate& child : p.children) flatten(child, false, out);
  } else if (p.atom == Atom::kNot) {
    flatten(p.children.front(), !negated, out);
  } else {
    out.emplace_back(&p, negated);
  }
}

// Reads a goal as one manipulation step; nullopt for a form the expert does not know.
std::optional<PlanStep> step_of_goal(const std::string& source,
                                     const std::vector<std::string>& objects) {
  const script::BoundPredicate bound = script::bind_predicate(source, objects);
  std::vector<std::pair<const Predicate*, bool>> atoms;
  flatten(bound.root, false, atoms);
  const auto object = [&](const Arg& a) { return objects[static_cast<size_t>(a.index)]; };
  const auto find = [&](Atom atom) -> const Predicate* {
    for (const auto& [p, negated] : atoms) {
      if (p->atom == atom && !negated) return p;
    }
    return nullptr;
  };
  PlanStep step;
  if (find(Atom::kAtHome)) {
    step.kind = StepKind::kHome;
  } else if (const Predicate* in = find(Atom::kIn)) {
    step.kind = StepKind::kPlace;
    step.object = object(in->args[0]);
    step.target = object(in->args[1]);
  } else if (const Predicate* on = find(Atom::kOn)) {
    step.object = object(on->args[0]);
    if (on->args[1].kind == Arg::Kind::kTable) {
      step.kind = StepKind::kPutBack;
      step.target = "table";
    } else {
      step.kind = StepKind::kPlace;
      step.target = object(on->args[1]);
    }
  } else if (const Predicate* held = find(Atom::kHeld)) {
    step.kind = StepKind::kRelease;
    step.object = object(held->args[1]);
    step.target = hand_name(held->args[0]);
  } else if (const Predicate* near = find(Atom::kNear)) {
    const Arg& a = near->args[0];
    const Arg& b = near->args[1];
    step.distance = near->args[2].number;
    if (a.kind == Arg::Kind::kObject &&
        (b.kind == Arg::Kind::kHand || b.kind == Arg::Kind::kAnyHand)) {
      step.kind = StepKind::kOffer;
      step.object = object(a);
      step.target = hand_name(b);
    } else if (a.kind == Arg::Kind::kRobot && b.kind == Arg::Kind::kObject) {
      step.kind = StepKind::kApproach;
      step.object = object(b);
    } else if (a.kind == Arg::Kind::kObject && b.kind == Arg::Kind::kObject) {
      step.kind = StepKind::kHover;
      step.object = object(a);
      step.target = object(b);
    } else {
      return std::nullopt;
    }
  } else if (const Predicate* grasped = find(Atom::kGrasped)) {
    step.kind = StepKind::kPick;
    step.object = object(grasped->args[1]);
    // grasped(robot, X) and not near(robot, C, d): keep holding X, get away from C.
    for (const auto& [p, negated] : atoms) {
      if (p->atom == Atom::kNear && negated && p->args[0].kind == Arg::Kind::kRobot &&
          p->args[1].kind == Arg::Kind::kObject) {
        step.kind = StepKind::kLeave;
        step.target = object(p->args[1]);
        step.distance = p->args[2].number;
      }
    }
  } else if (find(Atom::kStill)) {
    step.kind = StepKind::kStill;
  } else {
    return std::nullopt;
  }
  return step;
}

// Objects the person lifts together with the robot: named by a human act of primitive `lift`.
std::vector<std::string> co_carried(const script::EpisodeSpec& episode) {
  std::vector<std::string> names;
  for (const auto& entry : episode.acts) {
    const script::Act& act = entry.value;
    if (act.actor != "human" || !act.motion || !act.motion->primitive || act.motion->primitive->value() != "lift") continue;
    for (const auto& param : act.motion->params) {
      const script::Expr& e = param.value.scalar.expr;
      if (param.name == "object" && e.kind == script::Expr::Kind::kString) names.push_back(e.text);
    }
  }
  return names;
}

// The steps on a co-carried object become co-carry steps, all with the surface it goes onto.
void mark_co_carry(const script::EpisodeSpec& episode, std::vector<PlanStep>& plan) {
  for (const std::string& object : co_carried(episode)) {
    std::string target;
    for (const PlanStep& step : plan) {
      if (step.object == object && !step.target.empty()) target = step.target;
    }
    for (PlanStep& step : plan) {
      if (step.object != object) continue;
      step.kind = StepKind::kCoCarry;
      step.target = target;
    }
  }
}

}  // namespace

std::string_view to_string(Competence competence) {
  switch (competence) {
    case Competence::kOracle: return "oracle";
    case Competence::kReactive: return "reactive";
    case Competence::kBlind: return "blind";
  }
  return "?";
}

std::string_view to_string(StepKind kind) {
  switch (kind) {
    case StepKind::kPick: return "pick";
    case StepKind::kPlace: return "place";
    case StepKind::kPutBack: return "put_back";
    case StepKind::kHover: return "hover";
    case StepKind::kOffer: return "offer";
    case StepKind::kRelease: return "release";
    case StepKind::kApproach: return "approach";
    case StepKind::kLeave: return "leave";
    case StepKind::kHome: return "home";
    case StepKind::kCoCarry: return "co_carry";
    case StepKind::kStill: return "still";
  }
  return "?";
}

std::vector<PlanStep> make_plan(const script::EpisodeSpec& episode, Competence competence) {
  std::vector<std::string> objects;
  for (const auto& entry : episode.scene.objects) objects.push_back(entry.name);
  const bool oracle = competence == Competence::kOracle;

  // Human acts that contradict a robot act, and the events that fire the contradiction.
  struct Contradiction {
    std::string robot_act, start, fired;
  };
  std::vector<Contradiction> contradictions;
  for (const auto& entry : episode.acts) {
    const script::Act& act = entry.value;
    if (act.actor != "human" || !act.contradicts) continue;
    contradictions.push_back({*act.contradicts, entry.name + ".start",
                              act.cue ? act.cue->at : entry.name + ".start"});
  }

  std::vector<PlanStep> plan;
  // The nominal plan when the acts do not state it.
  for (const NominalGoal& nominal : kNominalGoals) {
    if (episode.task != nominal.task) continue;
    const std::optional<PlanStep> place = step_of_goal(nominal.goal, objects);
    HRIB_CHECK(place.has_value()) << nominal.goal;
    PlanStep pick{"", StepKind::kPick, place->object, "", 0, "", "", ""};
    // The oracle drops it when a robot act triggered by a disruption (the stand-down) starts.
    if (oracle) {
      for (const auto& entry : episode.acts) {
        if (entry.value.actor != "robot" || !entry.value.after) continue;
        const script::Act* trigger = find_act(episode, act_of_event(*entry.value.after));
        if (trigger && trigger->disruption) {
          pick.dropped_by = *entry.value.after;
          pick.pause_on = act_of_event(*entry.value.after) + ".start";
        }
      }
    }
    PlanStep put = *place;
    put.dropped_by = pick.dropped_by;
    put.pause_on = pick.pause_on;
    plan.push_back(pick);
    plan.push_back(put);
  }

  for (const auto& entry : episode.acts) {
    const script::Act& act = entry.value;
    if (act.actor != "robot") continue;
    if (!act.goal) {
      throw core::InputError("act " + entry.name, "a robot act with a goal", "no goal");
    }
    std::optional<PlanStep> step = step_of_goal(act.goal->source, objects);
    if (!step) {
      throw core::InputError("act " + entry.name,
                             "a goal the expert knows (grasped, in, on, near, held, at_home, still)",
                             "'" + act.goal->source + "'");
    }
    step->act = entry.name;
    // Contradicted: the oracle pauses when the contradicting act starts, drops it when fired.
    for (const Contradiction& c : contradictions) {
      if (c.robot_act == entry.name && oracle) {
        step->dropped_by = c.fired;
        step->pause_on = c.start;
      }
    }
    if (act.after) {
      const script::Act* trigger = find_act(episode, act_of_event(*act.after));
      const bool by_contradiction = trigger && trigger->contradicts.has_value();
      const bool by_disruption = trigger && trigger->disruption;
      if (!oracle && by_contradiction) continue;  // keeps the original instruction
      if (!oracle && by_disruption && step->kind == StepKind::kHome) continue;  // no stand-down
      const bool waits = oracle || (competence == Competence::kReactive && !by_disruption);
      if (waits) step->after = *act.after;
    }
    plan.push_back(*step);
  }
  mark_co_carry(episode, plan);
  return plan;
}

}  // namespace hribench::policy
