#include "eval/script_contract.h"

#include "core/errors.h"

namespace hribench::eval {
namespace {

CueKind cue_kind(const std::string& kind, const std::string& act) {
  if (kind == "go") return CueKind::kGo;
  if (kind == "stop") return CueKind::kStop;
  if (kind == "intrusion") return CueKind::kIntrusion;
  throw core::InputError("act " + act + ": cue kind", "go, stop or intrusion", "'" + kind + "'");
}

}  // namespace

ScenarioContract contract_from_act_graph(const script::ActGraph& graph) {
  ScenarioContract contract;
  const auto name = [&](int event) { return graph.event_names.at(static_cast<size_t>(event)); };
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
      if (act.contradicts >= 0) contract.contradiction = true;
      continue;
    }
    contract.robot_acts.push_back({act.name, std::nullopt});
    const script::RobotConstraints& c = act.constraints;
    if (c.after >= 0) contract.orders.push_back({OrderKind::kAfter, act.name, name(c.after), "", "", 0});
    // `within`: the act must start within that many seconds of its `after` event (a go cue).
    if (c.within >= 0 && c.after >= 0) {
      contract.cues.push_back({act.name, name(c.after), CueKind::kGo, c.within, std::nullopt});
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
  return contract;
}

}  // namespace hribench::eval
