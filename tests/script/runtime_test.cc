#include "script/runtime.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "script/check.h"
#include "script/sample.h"
#include "script/schema_io.h"

namespace hribench::script {
namespace {

// Acts fire by time (wave), by after + delay (point), by a predicate (stop), are skipped by
// unless (never), superseded by a later act of the same hand (grab ends stop); the robot act
// ends when its goal first holds.
const char* kScript = R"(
hribench: 1
task: runtime_probe
role: instructor
instruction: "Put the cube on the plate when the person says go."
horizon: 20
scene:
  objects:
    cube: {kind: cube, pose: {xy: [0.5, 0.0]}}
    plate: {kind: plate, pose: {xy: [0.5, 0.3]}}
acts:
  wave:
    actor: human
    onset: 1.0
    motion: {primitive: go, hand: right, raise: 0.5, gesture: 1.0, lower: 0.5}
    cue: {at: wave.gesture, window: 2.0}
  point:
    actor: human
    after: wave.end
    delay: 0.5
    motion: {primitive: point, hand: left, target: plate, prep: 0.25, stroke: 0.5, hold: 1.0, retract: 0.75}
  stop:
    actor: human
    when: near(robot, cube, 0.1)
    motion: {primitive: stop, hand: right, raise: 0.5, hold: 1.0, lower: 0.5}
  never:
    actor: human
    after: wave.start
    delay: 0.25
    unless: still(robot)
    motion: {primitive: withdraw, hand: left, duration: 0.5}
  grab:
    actor: human
    after: stop.hold
    delay: 0.25
    motion: {primitive: withdraw, hand: right, duration: 0.5}
  move:
    actor: robot
    goal: on(cube, plate)
    after: wave.gesture
success:
  - on(cube, plate)
)";

ObjectState box(double x, double y, double z, double hx, double hy, double hz) {
  ObjectState o;
  o.X_WO.translation = core::Vec3(x, y, z);
  o.half_extents = core::Vec3(hx, hy, hz);
  o.p_WO_initial = o.X_WO.translation;
  return o;
}

// The world at step k (20 Hz): the TCP reaches the cube at step 90, the cube rests on the plate
// from step 150.
WorldSnapshot world_at(int k) {
  WorldSnapshot w;
  w.time = k * 0.05;
  const bool on_plate = k >= 150;
  w.objects = {on_plate ? box(0.5, 0.3, 0.795, 0.025, 0.025, 0.025) : box(0.5, 0.0, 0.775, 0.025, 0.025, 0.025),
               box(0.5, 0.3, 0.76, 0.1, 0.1, 0.01)};
  w.X_WT.translation = k >= 90 ? core::Vec3(0.5, 0.0, 0.80) : core::Vec3(0.3, -0.3, 1.1);
  w.hands[kLeftHand].p_W = core::Vec3(1.5, 0.3, 0.9);
  w.hands[kRightHand].p_W = core::Vec3(1.5, -0.3, 0.9);
  return w;
}

ActGraph compile_probe() {
  const std::vector<Problem> problems = check_text(kScript, "probe.yaml");
  std::string all;
  for (const Problem& p : problems) all += p.text() + "\n";
  EXPECT_TRUE(problems.empty()) << all;
  std::vector<core::InputError> errors;
  const Scenario scenario = parse_scenario(kScript, "probe.yaml", errors);
  return compile(sample(scenario, 1));
}

TEST(RuntimeTest, ActsFireByTimeAfterDelayAndPredicate) {
  const ActGraph graph = compile_probe();
  RuntimeState state = make_runtime(graph);
  for (int k = 0; k <= 200; ++k) step(graph, state, world_at(k));
  const auto at = [&](const char* name) { return event_time(graph, state, name); };
  // By time: onset 1.0, phases raise 0.5, gesture 1.0, lower 0.5.
  EXPECT_EQ(at("wave.start"), 1.0);
  EXPECT_EQ(at("wave.raise"), 1.0);
  EXPECT_EQ(at("wave.gesture"), 1.5);
  EXPECT_EQ(at("wave.lower"), 2.5);
  EXPECT_EQ(at("wave.end"), 3.0);
  // By after + delay: wave.end + 0.5, then prep 0.25, stroke 0.5, hold 1.0, retract 0.75.
  EXPECT_EQ(at("point.start"), 3.5);
  EXPECT_EQ(at("point.stroke"), 3.75);
  EXPECT_EQ(at("point.hold"), 4.25);
  EXPECT_EQ(at("point.retract"), 5.25);
  EXPECT_EQ(at("point.end"), 6.0);
  // By a predicate: the step that first sees the TCP within 0.1 m of the cube.
  EXPECT_EQ(at("stop.start"), world_at(90).time);
  EXPECT_EQ(at("stop.hold"), world_at(90).time + 0.5);
  // Superseded: grab (same hand) starts 0.25 s into stop.hold and ends stop there.
  EXPECT_EQ(at("grab.start"), at("stop.hold") + 0.25);
  EXPECT_EQ(at("stop.end"), at("grab.start"));
  EXPECT_TRUE(std::isnan(at("stop.lower")));
  EXPECT_EQ(at("grab.end"), at("grab.start") + 0.5);
  // Skipped: the robot was still (for 0.2 s) when `never` was due at wave.start + 0.25.
  EXPECT_EQ(at("never.skipped"), 1.25);
  EXPECT_TRUE(std::isnan(at("never.start")));
  // The robot act ends when its goal first holds; the success predicate's change is an event.
  EXPECT_EQ(at("move.end"), world_at(150).time);
  EXPECT_EQ(at("on(cube, plate):true"), world_at(150).time);
  EXPECT_TRUE(std::isnan(at("move.start")));  // observed by the metrics, not here
  EXPECT_LT(state.failed_at, 0.0);
  // The log is in time order.
  for (size_t i = 1; i < state.events.size(); ++i) {
    EXPECT_LE(state.events[i - 1].time, state.events[i].time) << graph.event_names[static_cast<size_t>(state.events[i].id)];
  }
}

TEST(RuntimeTest, CompiledGraphCarriesWhatTheMetricsNeed) {
  const ActGraph graph = compile_probe();
  ASSERT_EQ(graph.acts.size(), 6U);
  const CompiledAct& wave = graph.acts[0];
  ASSERT_TRUE(wave.cue.has_value());
  EXPECT_EQ(graph.event_names[static_cast<size_t>(wave.cue->event)], "wave.gesture");
  EXPECT_EQ(wave.cue->window, 2.0);
  EXPECT_EQ(wave.cue->kind, "go");
  EXPECT_EQ(wave.hand, kRightHand);
  const CompiledAct& move = graph.acts[5];
  EXPECT_FALSE(move.human);
  EXPECT_EQ(graph.event_names[static_cast<size_t>(move.constraints.after)], "wave.gesture");
  EXPECT_EQ(move.constraints.before, -1);
  EXPECT_EQ(graph.objects, (std::vector<std::string>{"cube", "plate"}));
  ASSERT_EQ(graph.success.size(), 1U);
  EXPECT_EQ(graph.predicates[static_cast<size_t>(graph.success[0])].source, "on(cube, plate)");
}

TEST(RuntimeTest, ResetReplaysIdentically) {
  const ActGraph graph = compile_probe();
  RuntimeState state = make_runtime(graph);
  for (int k = 0; k <= 200; ++k) step(graph, state, world_at(k));
  const std::vector<Event> first = state.events;
  reset(graph, state);
  EXPECT_TRUE(state.events.empty());
  for (int k = 0; k <= 200; ++k) step(graph, state, world_at(k));
  ASSERT_EQ(state.events.size(), first.size());
  for (size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(state.events[i].id, first[i].id);
    EXPECT_EQ(state.events[i].time, first[i].time);
  }
}

// A waiting phase with `until` lasts at least its minimum and ends when the predicate held.
TEST(RuntimeTest, WaitingPhaseEndsOnItsSignal) {
  const std::string script = R"(
hribench: 1
task: offer_probe
role: collaborator
instruction: "Take the cube."
horizon: 20
scene:
  objects:
    cube: {kind: cube, held_by: human.right}
acts:
  offer:
    actor: human
    motion:
      primitive: offer
      hand: right
      object: cube
      zone: {center: [0.6, 0.0, 1.0], radius: 0.05}
      duration: 1.0
      settle: 0.25
      hold: 0.5
      release: 0.25
      retract: 0.75
      until: held_for(robot, cube, 0.2)
    fails: false
  take:
    actor: robot
    goal: grasped(robot, cube)
success:
  - grasped(robot, cube)
)";
  const std::vector<Problem> problems = check_text(script, "offer.yaml");
  ASSERT_TRUE(problems.empty()) << problems.front().text();
  std::vector<core::InputError> errors;
  const ActGraph graph = compile(sample(parse_scenario(script, "offer.yaml", errors), 1));
  RuntimeState state = make_runtime(graph);
  for (int k = 0; k <= 100; ++k) {
    WorldSnapshot w = world_at(0);
    w.time = k * 0.05;
    const bool grasped = k >= 60;  // fingers on the cube from t = 3.0
    w.objects[0].left_finger_contact = grasped;
    w.objects[0].right_finger_contact = grasped;
    step(graph, state, w);
  }
  const auto at = [&](const char* name) { return event_time(graph, state, name); };
  EXPECT_EQ(at("offer.hold"), 1.0);
  EXPECT_EQ(at("offer.hold_stable"), 1.25);
  // held_for 0.2 s first holds at the step of t = 3.2; the minimum (0.5 s) has passed.
  EXPECT_EQ(at("offer.release"), 64 * 0.05);
  EXPECT_EQ(at("offer.retract"), at("offer.release") + 0.25);
  EXPECT_EQ(at("take.end"), 60 * 0.05);
}

TEST(RuntimeTest, CompileRejectsAPredicateOnAnUnknownObject) {
  std::vector<core::InputError> errors;
  EpisodeSpec spec = sample(parse_scenario(kScript, "probe.yaml", errors), 1);
  spec.success[0].source = "on(mug, plate)";
  EXPECT_THROW(compile(spec), core::InputError);
}

}  // namespace
}  // namespace hribench::script
