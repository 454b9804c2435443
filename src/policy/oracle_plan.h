#pragma once
// The plan of the oracle expert and its scripted baselines: the episode's robot acts, read as
// manipulation steps (pick, place, hand over, go home, ...), with what each competence level
// waits for and what drops a step. Pure functions of the sampled episode (no physics), so the
// plan of every task can be tested on its own.
//
// Competence levels (issue 6):
//   oracle   — waits for every act's `after` event, drops an act once a contradicting human
//              act starts (and follows the acts triggered by it), stands down after a
//              disruption; the policy adds speed-and-separation monitoring and re-planning.
//   reactive — waits for `after` events of cue acts, but ignores contradictions (executes the
//              contradicted act, never the acts triggered by the contradiction), does not wait
//              for a disruption to end and does not stand down (skips at_home acts triggered by
//              a disruption).
//   blind    — as reactive, and also ignores every `after` event: starts at t = 0.
//
// Where the acts do not state the instructed plan (X3 someone_else_places: the only robot act
// is the stand-down), the nominal plan is taken from a per-task table (kNominalGoals), steps
// with an empty act name that precede the script's acts.

#include <string>
#include <vector>

#include "script/scenario.h"

namespace hribench::policy {

enum class Competence { kOracle, kReactive, kBlind };
std::string_view to_string(Competence competence);  // "oracle" | "reactive" | "blind"

enum class StepKind {
  kPick,          // grasp `object` top-down and lift it
  kPlace,         // put `object` in or on `target` (a container or surface object)
  kPutBack,       // put `object` back on the table where it was picked, release it
  kHover,         // hold `object` near `target` at a safe height (within `distance`)
  kOffer,         // bring `object` to the human hand `target` ("human.left|right")
  kRelease,       // open the gripper once the hand `target` holds `object`, then withdraw
  kApproach,      // bring the open gripper near `object` (within `distance`)
  kLeave,         // holding `object`, take the gripper farther than `distance` from `target`
  kHome,          // return to the start pose, gripper open, and stay still
  kCoCarry,       // hold `object` together with the human and follow the human's end until it
                  // rests on `target`, then release (one step per robot act on an object the
                  // person lifts with the robot: a human act of primitive `lift` names it)
  kStill,         // stay still
};
std::string_view to_string(StepKind kind);

struct PlanStep {
  std::string act;      // the robot act it comes from; empty for a nominal step (kNominalGoals)
  StepKind kind = StepKind::kStill;
  std::string object;   // the manipulated object ("" for kHome, kStill)
  std::string target;   // container/surface object, "table", or "human.left|right"
  double distance = 0;  // kHover / kApproach: within this, m
  std::string after;    // event this competence waits for before starting ("" none)
  std::string dropped_by;  // event whose occurrence drops the step ("" never)
  std::string pause_on;    // event after which the step pauses until `dropped_by` ("" none)
  bool operator==(const PlanStep&) const = default;
};

// Nominal goals of tasks whose robot acts do not state the instructed plan, by task name:
// {"someone_else_places", "on(item, plate)"}.
struct NominalGoal {
  const char* task;
  const char* goal;
};
inline constexpr NominalGoal kNominalGoals[] = {{"someone_else_places", "on(item, plate)"}};

// The steps of `episode` for `competence`, in execution order (the script's act order; a
// step runs once every step before it is done or dropped). Throws core::InputError naming
// the act when a robot act's goal has a form the expert does not know.
std::vector<PlanStep> make_plan(const script::EpisodeSpec& episode, Competence competence);

}  // namespace hribench::policy
