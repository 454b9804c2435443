#pragma once
// Phase timing of a human act's motion, from the motion primitive catalog
// (human/primitives.h) and the act's drawn parameters. The runtime uses it to fire phase
// events (ACT.PHASE) and the validator to compute the earliest time of every event.
//
// A phase's duration is the number parameter of the same name (point: prep, stroke, hold,
// retract), except: the first movement phase uses `duration` when no parameter has its name;
// offer's `hold` phase uses `settle` and its `hold_stable` phase uses `hold`; reach's `hold`
// uses `dwell`; walk_to's `turn` and `face` use `turn` and its `walk` is the distance to `to`
// divided by 0.75 x `speed`. A missing parameter takes the catalog default. An imported clip
// has one phase, `play`, lasting the motion's `duration`.

#include <string>
#include <vector>

#include "core/math.h"
#include "human/primitives.h"
#include "script/scenario.h"

namespace hribench::script {

struct PhaseTiming {
  std::string name;
  double duration = 0;  // s; for a waiting phase, the minimum
  bool waits = false;   // can be held open by the motion's `until` predicate
};

// The phase names of a primitive ("play" for a clip).
std::vector<std::string> phase_names(const human::PrimitiveInfo& primitive);

// Name of the number parameter that sets phase `phase` of `primitive` (empty if none).
std::string phase_parameter(const human::PrimitiveInfo& primitive, size_t phase);

// Timing of a resolved motion (every value literal). `stand` is the person's start
// position (walk_to; only x and y are used). Throws InputError when the primitive is unknown.
std::vector<PhaseTiming> phase_timing(const Motion& motion, const core::Vec3& stand);

// The motion's `onset` parameter (wait between the act's start and its first phase), s.
double motion_onset(const Motion& motion);

// The value of a resolved parameter, or nullptr.
const ValueTree* find_param(const Motion& motion, const std::string& name);

// The primitive catalog as a Markdown table (name, phases with the parameter that times each,
// waiting phases marked *, other parameters), for docs/scenario-scripts.md.
std::string primitive_reference_markdown();

}  // namespace hribench::script
