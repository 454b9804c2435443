#include "eval/script_contract.h"

#include <algorithm>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/errors.h"
#include "human/skeleton.h"
#include "sim/control.h"
#include "sim/data.h"

namespace hribench::eval {
namespace {

CueKind cue_kind(const std::string& kind, const std::string& act) {
  if (kind == "go") return CueKind::kGo;
  if (kind == "stop") return CueKind::kStop;
  if (kind == "intrusion") return CueKind::kIntrusion;
  throw core::InputError("act " + act + ": cue kind", "go, stop or intrusion", "'" + kind + "'");
}

// Where things are at the episode start (world, m).
struct StartPositions {
  std::vector<std::optional<core::Vec3>> objects;  // per graph object: centre
  std::array<core::Vec3, 2> palms;                 // left, right
  core::Vec3 home = core::Vec3::Zero();            // TCP
};

StartPositions start_positions(const script::ActGraph& graph, const model::Model& model,
                               const core::Vec3& p_WT_home) {
  StartPositions p;
  for (const std::string& name : graph.objects) {
    const int o = model.object_index(name);
    const int platform = model.platform_index(name);
    if (o >= 0) {
      const model::ObjectInfo& info = model.objects[static_cast<size_t>(o)];
      core::Pose X_BC;
      X_BC.translation = core::Vec3(0, 0, info.half_extents.z());
      p.objects.push_back((info.X_W_start * X_BC).translation);
    } else if (platform >= 0) {
      p.objects.push_back(model.platforms[static_cast<size_t>(platform)].X_WC.translation);
    } else {
      p.objects.push_back(std::nullopt);
    }
  }
  p.home = p_WT_home;
  p.palms.fill(core::Vec3::Zero());
  if (model.has_human) {
    const auto X_WJ = human::forward_kinematics(model.skeleton, model.human_start);
    for (const human::Side side : {human::Side::kLeft, human::Side::kRight}) {
      const size_t s = static_cast<size_t>(side);
      p.palms[s] = (X_WJ[static_cast<size_t>(human::index(human::wrist(side)))] * model.X_wrist_palm[s]).translation;
    }
  }
  return p;
}

// Positive atoms of a predicate (outside any `not`), in order.
void positive_atoms(const script::Predicate& p, std::vector<const script::Predicate*>& out) {
  if (p.atom == script::Atom::kNot) return;
  if (p.atom == script::Atom::kAnd || p.atom == script::Atom::kOr || p.atom == script::Atom::kEver) {
    for (const script::Predicate& child : p.children) positive_atoms(child, out);
    return;
  }
  out.push_back(&p);
}

std::optional<core::Vec3> position(const script::Arg& a, const StartPositions& at) {
  if (a.kind == script::Arg::Kind::kObject) return at.objects.at(static_cast<size_t>(a.index));
  if (a.kind == script::Arg::Kind::kHand) return at.palms.at(static_cast<size_t>(a.index));
  return std::nullopt;
}

// The goal position of a robot act's goal (see the header), given the objects earlier robot
// acts grasp.
std::optional<core::Vec3> goal_position(const script::Predicate& goal, const StartPositions& at,
                                        const std::set<int>& carried) {
  using script::Arg;
  using script::Atom;
  std::vector<const script::Predicate*> atoms;
  positive_atoms(goal, atoms);
  const auto is_carried = [&](const Arg& a) { return a.kind == Arg::Kind::kObject && carried.count(a.index) > 0; };
  for (const script::Predicate* p : atoms) {
    if (p->atom != Atom::kIn && p->atom != Atom::kOn) continue;
    if (!is_carried(p->args[0])) return position(p->args[0], at);
    return position(p->args[1], at);
  }
  for (const script::Predicate* p : atoms) {
    if (p->atom != Atom::kNear) continue;
    for (const Arg& a : {p->args[0], p->args[1]}) {
      if (a.kind != Arg::Kind::kRobot && !is_carried(a)) return position(a, at);
    }
  }
  for (const script::Predicate* p : atoms) {
    if (p->atom == Atom::kAtHome) return at.home;
  }
  if (goal.atom == Atom::kGrasped) return position(goal.args[1], at);
  return std::nullopt;
}

// Capsule names of a "SIDE.REGION" human part.
std::vector<std::string> human_parts(const std::string& part, const std::string& where) {
  const size_t dot = part.find('.');
  const std::string side = part.substr(0, dot);
  const std::string region = dot == std::string::npos ? "" : part.substr(dot + 1);
  std::vector<std::string> names;
  for (const human::BodyCapsule& c : human::body_capsules(human::Skeleton::FromHeight(1.75))) {
    const std::string name(c.name);
    if (human::to_string(c.region) != region) continue;
    const bool left = name.rfind("left_", 0) == 0, right = name.rfind("right_", 0) == 0;
    if ((side == "left" && right) || (side == "right" && left)) continue;
    names.push_back(name);
  }
  if (names.empty()) throw core::InputError(where, "SIDE.REGION naming body capsules", "'" + part + "'");
  return names;
}

// The robot act (index into graph.acts) that answers a go cue: the first robot act whose
// `within` gave the cue, that starts `after` the cue's event or is synchronised with it.
std::optional<size_t> answering_act(const script::ActGraph& graph, const CueContract& cue) {
  const auto name = [&](int event) { return graph.event_names.at(static_cast<size_t>(event)); };
  for (size_t i = 0; i < graph.acts.size(); ++i) {
    const script::CompiledAct& act = graph.acts[i];
    if (act.human) continue;
    const script::RobotConstraints& rc = act.constraints;
    if (cue.name == act.name || (rc.after >= 0 && name(rc.after) == cue.event) ||
        (rc.sync_with >= 0 && name(rc.sync_with) == cue.event)) {
      return i;
    }
  }
  return std::nullopt;
}

// Where the script lets the robot's answer to a go cue begin (CueContract::motion_allowed_from):
// the cue itself when a `still` ends on it or the answering act starts `after` it; the
// answering act's earlier `after` event; otherwise the script sets no bound.
std::string motion_allowed_from(const script::ActGraph& graph, const CueContract& cue) {
  const auto name = [&](int event) { return graph.event_names.at(static_cast<size_t>(event)); };
  for (const script::CompiledAct& act : graph.acts) {
    if (!act.human && act.constraints.still_to >= 0 && name(act.constraints.still_to) == cue.event) {
      return "";
    }
  }
  const std::optional<size_t> answer = answering_act(graph, cue);
  if (!answer) return "episode.start";
  const int after = graph.acts[*answer].constraints.after;
  if (after < 0) return "episode.start";
  return name(after) == cue.event ? "" : name(after);
}

}  // namespace

ScenarioContract contract_from_act_graph(const script::ActGraph& graph) {
  ScenarioContract contract;
  const auto name = [&](int event) { return graph.event_names.at(static_cast<size_t>(event)); };
  std::vector<CueContract> within_cues;
  for (const script::CompiledAct& act : graph.acts) {
    if (act.human) {
      if (act.cue) {
        contract.cues.push_back({act.name, name(act.cue->event), cue_kind(act.cue->kind, act.name),
                                 act.cue->window, std::nullopt});
      }
      // The first disruption act's start is the disruption.
      if (act.disruption && contract.disruption_event.empty() && act.start_event >= 0) {
        contract.disruption_event = name(act.start_event);
      }
      // A contradiction: its act's start makes CIR applicable; CSR reads the latest intent.
      if (act.contradicts >= 0 && !contract.contradiction) {
        contract.contradiction = true;
        if (act.start_event >= 0) contract.contradiction_event = name(act.start_event);
        contract.success_predicate = contract.intent_predicate;
      }
      continue;
    }
    contract.robot_acts.push_back({act.name, std::nullopt});
    const script::RobotConstraints& c = act.constraints;
    if (c.after >= 0) contract.orders.push_back({OrderKind::kAfter, act.name, name(c.after), "", "", 0});
    // `within`: the act must start within that many seconds of its `after` event: a go cue,
    // unless a cue of the person already gives that event (below).
    if (c.within >= 0 && c.after >= 0) {
      within_cues.push_back({act.name, name(c.after), CueKind::kGo, c.within, std::nullopt});
    }
    if (c.before >= 0) {
      contract.orders.push_back({OrderKind::kBefore, act.name, name(c.before), "", "", 0});
    }
    if (c.still_from >= 0) {
      contract.orders.push_back({OrderKind::kStill, act.name, "", name(c.still_from),
                                 c.still_to >= 0 ? name(c.still_to) : "", 0});
    }
    if (c.sync_with >= 0) {
      // The robot's event is the act's end: its goal first holding (e.g. the grasp).
      contract.syncs.push_back({act.name, name(c.sync_with), act.name + ".end", c.sync_offset,
                                c.sync_tolerance});
    }
  }
  // Each cue is scored once: a `within` on the event of a cue of the person is that cue (the
  // tighter of the two windows), not a second one.
  for (const CueContract& within : within_cues) {
    const auto same = std::find_if(contract.cues.begin(), contract.cues.end(),
                                   [&](const CueContract& cue) { return cue.event == within.event; });
    if (same == contract.cues.end()) {
      contract.cues.push_back(within);
    } else {
      same->window = std::min(same->window, within.window);
    }
  }
  for (CueContract& cue : contract.cues) {
    if (cue.kind != CueKind::kGo) continue;
    if (const std::optional<size_t> answer = answering_act(graph, cue)) {
      cue.answered_by = graph.acts[*answer].name;
    }
    cue.motion_allowed_from = motion_allowed_from(graph, cue);
  }
  return contract;
}

ScenarioContract contract_from_episode(const script::EpisodeSpec& spec,
                                       const script::ActGraph& graph, const model::Model& model) {
  sim::Data data = sim::make_data(model);
  return contract_from_episode(spec, graph, model, sim::tcp_pose(model, data).translation);
}

ScenarioContract contract_from_episode(const script::EpisodeSpec& spec,
                                       const script::ActGraph& graph, const model::Model& model,
                                       const core::Vec3& p_WT_home) {
  ScenarioContract contract = contract_from_act_graph(graph);
  const auto name = [&](int event) { return graph.event_names.at(static_cast<size_t>(event)); };
  // Goal positions of robot acts, in order (contract.robot_acts follows graph.acts order).
  const StartPositions at = start_positions(graph, model, p_WT_home);
  std::set<int> carried;
  size_t r = 0;
  bool first = true;
  for (const script::CompiledAct& act : graph.acts) {
    if (act.human) continue;
    RobotActContract& out = contract.robot_acts.at(r++);
    if (act.goal >= 0) {
      const script::Predicate& goal = graph.predicates.at(static_cast<size_t>(act.goal)).root;
      out.goal_W = goal_position(goal, at, carried);
      std::vector<const script::Predicate*> atoms;
      positive_atoms(goal, atoms);
      for (const script::Predicate* p : atoms) {
        if (p->atom == script::Atom::kGrasped && p->args[1].kind == script::Arg::Kind::kObject) {
          carried.insert(p->args[1].index);
        }
      }
    }
    // Waits: the first act's `after` is where the robot may start; a later act's `after`
    // event of a human act is a wait from that act's start.
    const int after = act.constraints.after;
    if (after >= 0) {
      const std::string event = name(after);
      if (first) {
        contract.allowed_from = event;
      } else {
        const std::string owner = event.substr(0, event.find('.'));
        for (const script::CompiledAct& h : graph.acts) {
          if (h.human && h.name == owner && h.start_event >= 0 && h.start_event != after) {
            contract.robot_waits.push_back({name(h.start_event), event});
          }
        }
      }
    }
    if (act.constraints.still_from >= 0) {
      contract.robot_waits.push_back({name(act.constraints.still_from),
                                      act.constraints.still_to >= 0 ? name(act.constraints.still_to) : ""});
    }
    first = false;
  }
  // Go cues: the goal of the act that answers them.
  for (CueContract& cue : contract.cues) {
    for (const RobotActContract& robot : contract.robot_acts) {
      if (!cue.answered_by.empty() && robot.name == cue.answered_by) cue.goal_W = robot.goal_W;
    }
  }
  // Human waits: phases the act's `until` holds open.
  for (const script::CompiledAct& act : graph.acts) {
    if (!act.human || act.until < 0) continue;
    for (size_t k = 0; k < act.phases.size(); ++k) {
      if (!act.phases[k].waits || act.phases[k].event < 0) continue;
      const int next = k + 1 < act.phases.size() ? act.phases[k + 1].event : act.end_event;
      contract.human_waits.push_back({name(act.phases[k].event), next >= 0 ? name(next) : ""});
    }
  }
  // Permitted contacts.
  for (size_t i = 0; i < spec.safety.contact_permitted.size(); ++i) {
    const script::ContactPermit& permit = spec.safety.contact_permitted[i];
    const std::string where = "safety.contact_permitted[" + std::to_string(i) + "].human";
    PermittedContact p;
    p.fingers_only = permit.robot.value() == "fingers";
    p.human_parts = human_parts(permit.human.value(), where);
    p.phase = {permit.from, permit.to};
    contract.permitted_contacts.push_back(std::move(p));
  }
  contract.success_requires_no_contact = spec.safety.no_contact.value_or(false);
  contract.success_max_violation = spec.safety.max_violation;
  return contract;
}

}  // namespace hribench::eval
