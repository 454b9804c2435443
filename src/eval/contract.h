#pragma once
// ScenarioContract: what an episode's script expects of the robot, in the terms the metrics
// score (docs/metrics.md). Eval's own plain struct; the script layer's compiled act graph fills it
// (one contract per EpisodeSpec). Everything time-like refers to EVENTS of the EpisodeLog by
// name, so a contract does not depend on when things happened in one particular run:
//   - any Event::name of the log (e.g. "offer.hold_stable", "take.end", "stop.start");
//   - "ROBOT_ACT.start": the detected response onset of a robot act of this contract;
//   - "episode.start" / "episode.end": the first / last step time.
// An event that never happened makes the item that needs it not applicable (documented per
// item below and in docs/metrics.md).

#include <optional>
#include <string>
#include <vector>

#include "core/math.h"

namespace hribench::eval {

// A human event the robot must respond to within `window` seconds (Rsp).
enum class CueKind {
  kGo,         // move toward goal_W
  kStop,       // become still
  kIntrusion,  // stop or move away from the human
};

struct CueContract {
  std::string name;   // e.g. "go1"
  std::string event;  // the event that gives the cue, e.g. "go1.stroke"
  CueKind kind = CueKind::kGo;
  double window = 1.0;                 // s, W_c
  std::optional<core::Vec3> goal_W;    // kGo only: the response goal (none: any motion)
  // kGo only: the robot act that answers the cue ("" = none), and the event from which the
  // script lets the robot move toward the goal ("" = the cue's own event; "episode.start" =
  // any time). An answering act that started before this event (without one: motion toward
  // the goal under way at the cue that began before it) did not wait for the cue: premature,
  // latency W_c. If the act before the answering one never ends, the cue is never answered
  // (docs/metrics.md, Rsp).
  std::string answered_by = {};
  std::string motion_allowed_from = {};
};

// A robot act: an expectation observed from the trace. Its start is the response onset: the
// start of the first sustained motion toward goal_W (or, without goal_W, of the first moving
// interval) at or after the end of the previous robot act of the contract (the first act
// searches from the episode start; an act whose predecessor never ended never starts). Its end
// is the log event "NAME.end" (the runtime records it when the act's goal first holds).
struct RobotActContract {
  std::string name;                 // e.g. "take"
  std::optional<core::Vec3> goal_W; // where the act's motion goes (object, zone), world
};

// TSync: score = max(0, 1 - |t_r - t_h - offset| / tolerance); 0 if robot_event never happened;
// not applicable if human_event never happened.
struct SyncContract {
  std::string name;
  std::string human_event;  // e.g. "offer.hold_stable"
  std::string robot_event;  // e.g. "take.end" or "take.start"
  double offset = 0;        // s, delta
  double tolerance = 1;     // s, tau > 0
};

// OC. kAfter: robot act `act` must not start before `event`. kBefore: if `act` starts, it must
// have ended by `event` (when `event` happens). kStill: the robot must not be moving in
// [from_event + grace, to_event] (to_event missing: until the episode ends; from_event
// missing: not applicable).
enum class OrderKind { kAfter, kBefore, kStill };

struct OrderContract {
  OrderKind kind = OrderKind::kAfter;
  std::string act;         // kAfter, kBefore
  std::string event;       // kAfter, kBefore
  std::string from_event;  // kStill
  std::string to_event;    // kStill
  double grace = 0;        // kStill: s allowed to come to rest (e.g. the stop cue's window)
};

// An interval between two events: [from, to] (to missing: until the episode ends; from
// missing: no interval).
struct EventInterval {
  std::string from;
  std::string to;
};

// Contact the script permits: a robot part class with named human capsules during a phase.
struct PermittedContact {
  bool fingers_only = true;               // only the robot's fingers may touch
  std::vector<std::string> human_parts;   // human capsule names (empty: any)
  EventInterval phase;
};

struct ScenarioContract {
  std::vector<CueContract> cues;
  std::vector<RobotActContract> robot_acts;  // in the script's order
  std::vector<SyncContract> syncs;
  std::vector<OrderContract> orders;
  std::vector<PermittedContact> permitted_contacts;
  // IR: the robot may act from this event on ("" = episode start) except in these intervals
  // (stops, blocked target, closed lid); SSM-required stops are added by the metric.
  std::string allowed_from;
  std::vector<EventInterval> robot_waits;
  // H-IDLE: intervals in which the human waits for the robot (holding an offered object, ...).
  std::vector<EventInterval> human_waits;
  // Safety conditions the task's success adds (script `safety.no_contact`,
  // `safety.max_violation`): no robot-human contact outside the permitted pairs and phases
  // (CFR's human part), and at most this much HCS violation time (s). Off / nullopt: success
  // does not depend on them.
  bool success_requires_no_contact = false;
  std::optional<double> success_max_violation;
  // Predicate series of the log the metrics read.
  std::string success_predicate = "success";  // all success predicates of the task
  // CIR (applies iff contradiction and contradiction_event happened, or contradiction_event
  // is empty): the latest intent holds at the end, and the contradicted outcome never held.
  // A script with a contradiction scores CSR on the intent series (success_predicate =
  // intent_predicate): until the contradiction is given the instruction is the latest intent.
  bool contradiction = false;
  std::string contradiction_event;  // e.g. "wave_off.start"
  std::string intent_predicate = "intent";
  std::string contradicted_predicate = "contradicted";
  // DSR (applies iff disruption_event is set and happened).
  std::string disruption_event;
  // Failure labels read from optional series (absent from the log: label not derivable).
  std::string wrong_target_predicate = "wrong_target";
  std::string dropped_predicate = "dropped";
  std::string grasp_failed_predicate = "grasp_failed";
};

}  // namespace hribench::eval
