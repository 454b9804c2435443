#pragma once
// The ScenarioContract of a compiled act graph (script/runtime.h): cues, robot acts and their
// constraints, disruption and contradiction.
//
// contract_from_act_graph(graph) fills what the graph alone says; goal positions, permitted
// contacts and wait intervals stay at the contract's defaults (onsets then fall back to "first
// moving").
//
// contract_from_episode(spec, graph, model) adds what needs the sampled episode and its model
// (the eval command and every script-driven run should use it):
//   - RobotActContract::goal_W: where the act's motion goes, world, at the episode start. From
//     the act's goal predicate, its atoms outside any `not`, first that applies:
//       in(o, c) / on(o, s): c / s (its centre; s = table: none) when an earlier robot act's
//         goal grasps o (the robot carries it there), else o (the robot must fetch it first);
//       near(A, B, d): the one of A, B that is not the robot nor the carried object (an
//         object's centre, a hand's palm);
//       at_home(robot): the TCP's home position;
//       grasped(robot, o) as the whole goal: o.
//     Anything else (moving away, lifting, letting go): none.
//   - CueContract::goal_W of go cues: the goal_W of the first robot act that starts `after` the
//     cue's event or is synchronised with it (a `within` cue: its own act's).
//   - permitted_contacts from safety.contact_permitted: robot "fingers" -> fingers_only, any
//     other robot part class -> fingers_only false (the contract has no finer class); human
//     "SIDE.REGION" -> the capsules of that region on that side (central capsules for either
//     side; "any" both sides); the phase [from, to].
//   - success_requires_no_contact / success_max_violation from safety.no_contact /
//     safety.max_violation.
//   - allowed_from: the `after` event of the first robot act, if it has one.
//   - robot_waits: every still interval (a stop cue's [still_from, still_to]); for every later
//     robot act that must start after a human act's event E, [that act's start, E] (a blocked
//     target, a closed lid, an offer not yet held).
//   - human_waits: a human act's waiting phases that end on the robot (those the act's `until`
//     predicate holds open: holding an offered object, an open receiving hand): [phase, next
//     phase] (or the act's end).
// The success series is "success" (the runner's driver reports the conjunction of the
// graph's success predicates under that name); with a contradiction also "intent" and
// "contradicted" (eval/script_driver.h), and success is read from "intent" (the latest
// intent: the instruction until the contradicting act starts, its success after);
// contradiction_event is the first contradicting act's start (CIR applies once it happened).

#include "eval/contract.h"
#include "model/model.h"
#include "script/runtime.h"
#include "script/scenario.h"

namespace hribench::eval {

ScenarioContract contract_from_act_graph(const script::ActGraph& graph);

// `graph` compiled from `spec`, `model` built from scene_spec_from_episode(spec). Throws
// core::InputError for a contact permit whose human part names no capsule.
// The robot's home TCP (a start position of robot goals) is computed on a fresh Data; the
// second form takes it (p_WT_home, world, m: the TCP right after sim::reset, e.g. from the
// episode's own Data) and makes no Data.
ScenarioContract contract_from_episode(const script::EpisodeSpec& spec,
                                       const script::ActGraph& graph, const model::Model& model);
ScenarioContract contract_from_episode(const script::EpisodeSpec& spec,
                                       const script::ActGraph& graph, const model::Model& model,
                                       const core::Vec3& p_WT_home);

}  // namespace hribench::eval
