#pragma once
// The ScenarioContract of a compiled act graph (script/runtime.h): cues, robot acts and their
// constraints, disruption and contradiction. What the graph does not carry yet stays at the
// contract's defaults and must be filled by the caller:
//   - goal positions of go cues and robot acts (world coordinates of the target object or
//     zone at the cue time): without them onsets fall back to "first moving";
//   - permitted contacts (the script's safety.contact_permitted), robot wait intervals and
//     human wait intervals, allowed_from.
// The success series is "success" (the runner's driver reports the conjunction of the
// graph's success predicates under that name).

#include "eval/contract.h"
#include "script/runtime.h"

namespace hribench::eval {

ScenarioContract contract_from_act_graph(const script::ActGraph& graph);

}  // namespace hribench::eval
