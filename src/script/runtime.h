#pragma once
// The act-graph runtime. compile(spec) builds the immutable ActGraph (it goes into Model);
// make_runtime() the mutable RuntimeState (it goes into Data). Each control step, step() is
// given the simulated time and the world (WorldSnapshot) and:
//   1. evaluates every predicate of the graph (triggers, goals, success) once;
//   2. starts waiting human acts whose triggers hold: `onset` (time), `after` EVENT + `delay`,
//      `when` PREDICATE; an act whose `unless` PREDICATE holds at that moment is skipped for
//      good (event ACT.skipped);
//   3. advances running human acts through their phases (timings from the drawn motion
//      parameters, script/phases.h); a waiting phase with a motion `until` predicate lasts at
//      least its nominal duration and ends when the predicate has held;
//   4. ends a running act when another human act starts with the same hand (superseded);
//   5. records robot ACT.end when the act's goal first holds (robot starts, the response
//      onsets, are observed by the metrics from the trace, not here);
//   6. records predicate changes of goals and success predicates.
// Event times: events scheduled by time (onset, after + delay, phase ends) carry their exact
// scheduled time, even when it falls between two steps; events caused by a predicate carry the
// time of the step that observed it. The human never waits for the robot.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "script/predicate.h"
#include "script/scenario.h"
#include "script/world.h"

namespace hribench::script {

inline constexpr int kNoHand = -1;  // acts of the whole body (idle, walk_to, clips without hand)

struct CompiledPhase {
  std::string name;     // empty for the motion's initial `onset` wait (no event)
  double duration = 0;  // s; minimum for a waiting phase
  bool waits = false;   // ends only once the act's `until` predicate has held
  int event = -1;       // event id of the phase's start, -1 for the unnamed onset wait
};

// A cue of a human act: the event the robot must respond to, and the window (docs/metrics.md Rsp).
struct CompiledCue {
  int event = -1;
  double window = 0;     // s
  std::string kind;      // go | stop | intrusion
};

// Constraints of a robot act, for the metrics (OC, Rsp, TSync); -1 = absent.
struct RobotConstraints {
  int after = -1;          // must start after this event
  int before = -1;         // must end before this event
  double within = -1;      // s after `after` to start; -1 = no window
  int sync_with = -1;      // TSync: human event h
  double sync_offset = 0;  // delta, s
  double sync_tolerance = 0;  // tau, s
  int still_from = -1, still_to = -1;  // must not move between these events
};

struct CompiledAct {
  std::string name;
  bool human = false;
  int hand = kNoHand;                  // Hand for human acts with a hand
  double onset = 0;                    // trigger: earliest start, s
  int after_event = -1;                // trigger (human) / order constraint (robot); -1 none
  double delay = 0;
  int when = -1, unless = -1, until = -1, goal = -1;  // indices into ActGraph::predicates
  bool fails = false;
  std::vector<CompiledPhase> phases;
  int start_event = -1, end_event = -1, skipped_event = -1;
  // For the metrics.
  std::optional<CompiledCue> cue;      // human
  bool disruption = false;             // human: DSR
  int contradicts = -1;                // human: index of the contradicted robot act (CIR)
  RobotConstraints constraints;        // robot
};

struct ActGraph {
  std::vector<std::string> objects;         // WorldSnapshot::objects order
  std::vector<CompiledAct> acts;            // spec order
  std::vector<BoundPredicate> predicates;   // every predicate the graph evaluates
  std::vector<int> watched;                 // predicates whose changes are events
  std::vector<int> watch_true_event, watch_false_event;  // per watched predicate
  std::vector<int> success;                 // success predicates
  std::vector<std::string> event_names;     // "offer.start", "offer.hold_stable", "in(item, bin):true"
  double horizon = 0;

  // The id of an event name, or -1.
  int event_id(std::string_view name) const;
};

// Builds the graph of a sampled episode. Throws InputError when a predicate or motion of the
// spec is invalid (a spec from a clean script never is).
ActGraph compile(const EpisodeSpec& spec);

struct Event {
  double time = 0;
  int id = -1;
};

enum class ActStatus { kWaiting, kRunning, kDone, kSkipped };

struct ActState {
  ActStatus status = ActStatus::kWaiting;
  double start = 0;         // s, when running or done
  size_t phase = 0;         // current phase index while running
  double phase_start = 0;   // s
  double until_since = -1;  // first time the `until` predicate held in the current phase
};

struct RuntimeState {
  std::vector<ActState> acts;
  std::vector<double> event_time;     // first occurrence of each event; NaN = not yet
  std::vector<Event> events;          // every event, in time order
  std::vector<PredicateMemory> memory;
  std::vector<char> value;            // predicate values at the last step
  std::vector<char> watched_value;    // last recorded value of each watched predicate
  double failed_at = -1;              // start of the first `fails` act, -1 = none
  std::vector<Event> pending;         // scratch for one step (kept to avoid allocations)
};

RuntimeState make_runtime(const ActGraph& graph);
void reset(const ActGraph& graph, RuntimeState& state);
// One control step at world.time (non-decreasing from call to call).
void step(const ActGraph& graph, RuntimeState& state, const WorldSnapshot& world);

// "offer.hold_stable" -> its first time, or NaN.
double event_time(const ActGraph& graph, const RuntimeState& state, std::string_view name);

}  // namespace hribench::script
