#include "eval/script_contract.h"

#include <gtest/gtest.h>

#include "core/errors.h"
#include "eval/metrics.h"
#include "eval/runner.h"
#include "eval/script_driver.h"
#include "policy/builtin.h"
#include "model/model.h"
#include "script/check.h"
#include "script/sample.h"
#include "support/mujoco_fixture.h"

namespace hribench::eval {
namespace {

// A hand-built graph shaped like the handover_h2r example of docs/scenario-scripts.md.
script::ActGraph handover_graph() {
  script::ActGraph g;
  g.event_names = {"offer.start", "offer.end", "offer.hold_stable", "take.start", "take.end",
                   "stop.start", "go.start"};
  script::CompiledAct offer;
  offer.name = "offer";
  offer.human = true;
  offer.start_event = 0;
  offer.end_event = 1;
  offer.cue = script::CompiledCue{2, 4.0, "go"};
  offer.disruption = true;
  script::CompiledAct take;
  take.name = "take";
  take.human = false;
  take.constraints.after = 2;
  take.constraints.sync_with = 2;
  take.constraints.sync_offset = 1.0;
  take.constraints.sync_tolerance = 1.5;
  take.constraints.still_from = 5;
  take.constraints.still_to = 6;
  g.acts = {offer, take};
  return g;
}

TEST(ScriptContract, CuesActsAndConstraints) {
  const ScenarioContract c = contract_from_act_graph(handover_graph());
  ASSERT_EQ(c.cues.size(), 1u);
  EXPECT_EQ(c.cues[0].event, "offer.hold_stable");
  EXPECT_EQ(c.cues[0].kind, CueKind::kGo);
  EXPECT_DOUBLE_EQ(c.cues[0].window, 4.0);
  ASSERT_EQ(c.robot_acts.size(), 1u);
  EXPECT_EQ(c.robot_acts[0].name, "take");
  ASSERT_EQ(c.orders.size(), 2u);
  EXPECT_EQ(c.orders[0].kind, OrderKind::kAfter);
  EXPECT_EQ(c.orders[0].event, "offer.hold_stable");
  EXPECT_EQ(c.orders[1].kind, OrderKind::kStill);
  EXPECT_EQ(c.orders[1].from_event, "stop.start");
  EXPECT_EQ(c.orders[1].to_event, "go.start");
  ASSERT_EQ(c.syncs.size(), 1u);
  EXPECT_EQ(c.syncs[0].human_event, "offer.hold_stable");
  EXPECT_EQ(c.syncs[0].robot_event, "take.end");
  EXPECT_DOUBLE_EQ(c.syncs[0].offset, 1.0);
  EXPECT_DOUBLE_EQ(c.syncs[0].tolerance, 1.5);
  EXPECT_EQ(c.disruption_event, "offer.start");
  EXPECT_FALSE(c.contradiction);
}

// Each cue is scored once: a robot act's `within` on the event of the person's cue is that cue
// (with the tighter window), not a second one (I1's point and put, I4's go and place); on an
// event no cue gives, it is a go cue of its own, named after the act.
TEST(ScriptContract, WithinOnACueEventIsThatCue) {
  script::ActGraph g = handover_graph();
  g.acts[1].constraints.within = 2.5;
  const ScenarioContract same = contract_from_act_graph(g);
  ASSERT_EQ(same.cues.size(), 1u);
  EXPECT_EQ(same.cues[0].name, "offer");
  EXPECT_EQ(same.cues[0].event, "offer.hold_stable");
  EXPECT_DOUBLE_EQ(same.cues[0].window, 2.5);
  g.acts[1].constraints.within = 6.0;
  EXPECT_DOUBLE_EQ(contract_from_act_graph(g).cues.at(0).window, 4.0);
  g.acts[0].cue.reset();
  const ScenarioContract own = contract_from_act_graph(g);
  ASSERT_EQ(own.cues.size(), 1u);
  EXPECT_EQ(own.cues[0].name, "take");
  EXPECT_EQ(own.cues[0].event, "offer.hold_stable");
  EXPECT_EQ(own.cues[0].kind, CueKind::kGo);
  EXPECT_DOUBLE_EQ(own.cues[0].window, 6.0);
}

// Where a go cue's answer may begin: at the cue when the answering act starts `after` it or a
// `still` ends on it; at the answering act's earlier `after` event; anywhere when the script
// sets no bound.
TEST(ScriptContract, MotionAllowedFromTheAnsweringActsAfter) {
  script::ActGraph g = handover_graph();
  EXPECT_EQ(contract_from_act_graph(g).cues.at(0).answered_by, "take");
  EXPECT_EQ(contract_from_act_graph(g).cues.at(0).motion_allowed_from, "");
  g.acts[1].constraints.after = 0;  // take after offer.start, synchronised with the cue
  EXPECT_EQ(contract_from_act_graph(g).cues.at(0).motion_allowed_from, "offer.start");
  g.acts[1].constraints.still_to = 2;  // ... but it must be still until the cue
  EXPECT_EQ(contract_from_act_graph(g).cues.at(0).motion_allowed_from, "");
  g.acts[1].constraints.still_to = 6;
  g.acts[1].constraints.after = -1;
  EXPECT_EQ(contract_from_act_graph(g).cues.at(0).motion_allowed_from, "episode.start");
  g.acts[1].constraints.sync_with = -1;  // no act answers the cue
  EXPECT_EQ(contract_from_act_graph(g).cues.at(0).answered_by, "");
  EXPECT_EQ(contract_from_act_graph(g).cues.at(0).motion_allowed_from, "episode.start");
}

TEST(ScriptContract, UnknownCueKindIsAnInputError) {
  script::ActGraph g = handover_graph();
  g.acts[0].cue->kind = "wave";
  try {
    contract_from_act_graph(g);
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "act offer: cue kind: expected go, stop or intrusion, got 'wave'");
  }
}

// A sampled task with its graph and model.
struct Task {
  script::EpisodeSpec spec;
  script::ActGraph graph;
  model::Model model;
  explicit Task(const std::string& path, uint64_t seed = 1)
      : spec(script::sample(script::load_scenario(path), seed)),
        graph(script::compile(spec)),
        model(model::build(scene_spec_from_episode(spec))) {}
  // Centre of an object at the start, from the spec (footprint) and the model (height).
  core::Vec3 centre(const std::string& name) const {
    const model::ObjectInfo& o = model.objects.at(static_cast<size_t>(model.object_index(name)));
    return o.X_W_start.translation + core::Vec3(0, 0, o.half_extents.z());
  }
};

using ScriptContractEpisode = hribench::testing::MujocoTest;

// The first seed (from 1) at which a script samples this variant.
uint64_t seed_with_variant(const std::string& path, const std::string& variant) {
  const script::Scenario scenario = script::load_scenario(path);
  for (uint64_t seed = 1; seed < 100; ++seed) {
    if (script::sample(scenario, seed).variant == variant) return seed;
  }
  ADD_FAILURE() << "no " << variant << " in 99 seeds of " << path;
  return 1;
}

const RobotActContract& act(const ScenarioContract& c, const std::string& name) {
  for (const RobotActContract& a : c.robot_acts) {
    if (a.name == name) return a;
  }
  throw std::runtime_error("no robot act " + name);
}

void expect_at(const std::optional<core::Vec3>& got, const core::Vec3& want, const std::string& what) {
  ASSERT_TRUE(got.has_value()) << what;
  EXPECT_LT((*got - want).norm(), 1e-9) << what << ": " << got->transpose() << " vs " << want.transpose();
}

// C1: fetch-like goals go to the item, a carried item's goal to its container; the hold the
// person keeps until the robot has the item is a human wait; fingers may touch the giving hand.
TEST_F(ScriptContractEpisode, HandoverGoalsWaitsAndPermittedContact) {
  const Task t("tasks/C1_handover_h2r.yaml");
  const ScenarioContract c = contract_from_episode(t.spec, t.graph, t.model);
  expect_at(act(c, "approach").goal_W, t.centre("item"), "approach");
  expect_at(act(c, "take").goal_W, t.centre("item"), "take");
  expect_at(act(c, "place").goal_W, t.centre("bin"), "place");
  EXPECT_EQ(c.allowed_from, "offer.start");
  ASSERT_EQ(c.robot_waits.size(), 2u);
  EXPECT_EQ(c.robot_waits[0].from, "offer.start");
  EXPECT_EQ(c.robot_waits[0].to, "offer.hold");
  EXPECT_EQ(c.robot_waits[1].to, "offer.release");
  ASSERT_EQ(c.human_waits.size(), 1u);
  EXPECT_EQ(c.human_waits[0].from, "offer.hold_stable");
  EXPECT_EQ(c.human_waits[0].to, "offer.release");
  ASSERT_EQ(c.permitted_contacts.size(), 1u);
  const PermittedContact& p = c.permitted_contacts[0];
  EXPECT_TRUE(p.fingers_only);
  const std::string hand = t.spec.vars[0].value.expr.text + "_hand";
  EXPECT_EQ(p.human_parts, std::vector<std::string>{hand});
  EXPECT_EQ(p.phase.from, "offer.hold_stable");
  EXPECT_EQ(p.phase.to, "offer.retract");
  // The go cue's goal: that of the act synchronised with it (take).
  ASSERT_EQ(c.cues.size(), 1u);
  EXPECT_EQ(c.cues[0].event, "offer.hold_stable");
  expect_at(c.cues[0].goal_W, t.centre("item"), "cue");
}

// I1: the robot may start at the point's stroke; the go cue and the put go to the target
// object first (it is not carried yet), not to the bin.
TEST_F(ScriptContractEpisode, PointPickGoesToTheTargetFirst) {
  const Task t("tasks/I1_point_pick.yaml");
  const ScenarioContract c = contract_from_episode(t.spec, t.graph, t.model);
  std::string target;
  for (const auto& v : t.spec.vars) {
    if (v.name == "target") target = v.value.expr.text;
  }
  ASSERT_FALSE(target.empty());
  expect_at(act(c, "put").goal_W, t.centre(target), "put");
  EXPECT_EQ(c.allowed_from, "point.stroke");
  ASSERT_FALSE(c.cues.empty());
  for (const CueContract& cue : c.cues) expect_at(cue.goal_W, t.centre(target), "cue " + cue.name);
  EXPECT_TRUE(c.robot_waits.empty());
  EXPECT_TRUE(c.permitted_contacts.empty());
  EXPECT_FALSE(c.success_requires_no_contact);
  EXPECT_FALSE(c.success_max_violation.has_value());
}

// I4 with a stop: the stop's still interval is a robot wait; C4: platforms are goals.
TEST_F(ScriptContractEpisode, StopIsARobotWaitAndPlatformsAreGoals) {
  const Task t("tasks/I4_stop_go.yaml", seed_with_variant("tasks/I4_stop_go.yaml", "with_stop"));
  const ScenarioContract stop = contract_from_episode(t.spec, t.graph, t.model);
  ASSERT_EQ(stop.robot_waits.size(), 1u);
  EXPECT_EQ(stop.robot_waits[0].from, "halt.hold");
  EXPECT_EQ(stop.robot_waits[0].to, "go_again.gesture");
  EXPECT_EQ(stop.allowed_from, "go.gesture");
  expect_at(act(stop, "place").goal_W, t.centre("cube"), "place");
  const Task lift("tasks/C4_co_lift.yaml");
  const ScenarioContract c = contract_from_episode(lift.spec, lift.graph, lift.model);
  expect_at(act(c, "hold_end").goal_W, lift.centre("plank"), "hold_end");
  EXPECT_FALSE(act(c, "lift_end").goal_W.has_value());
  const model::PlatformInfo& platform = lift.model.platforms.at(static_cast<size_t>(lift.model.platform_index("platform")));
  expect_at(act(c, "follow").goal_W, platform.X_WC.translation, "follow");
  expect_at(act(c, "lower_end").goal_W, platform.X_WC.translation, "lower_end");
}

// X4: the blocked plate is a robot wait from the blocking act's start to its retract.
TEST_F(ScriptContractEpisode, BlockedTargetIsARobotWait) {
  const Task t("tasks/X4_blocked_target.yaml", seed_with_variant("tasks/X4_blocked_target.yaml", "hand_block"));
  const ScenarioContract c = contract_from_episode(t.spec, t.graph, t.model);
  ASSERT_EQ(c.robot_waits.size(), 1u);
  EXPECT_EQ(c.robot_waits[0].from, "block.start");
  EXPECT_EQ(c.robot_waits[0].to, "block.retract");
  expect_at(act(c, "carry").goal_W, t.centre("plate"), "carry");
  expect_at(act(c, "place").goal_W, t.centre("plate"), "place");
  // The script's safety conditions ("no contact" in docs/tasks.md) reach the contract.
  EXPECT_TRUE(c.success_requires_no_contact);
  EXPECT_EQ(c.success_max_violation, t.spec.safety.max_violation);
}

// The metrics score a driven episode with this contract: CIR and CSR read the driver's intent
// and contradicted series of an I5 contradiction episode. A robot that never grasps is never
// waved off: the contradiction is not given (no CIR), and the instruction (the item on the
// plate) stays the latest intent, although the cancel variant's success predicates hold.
TEST_F(ScriptContractEpisode, MetricsScoreADrivenContradictionEpisode) {
  const Task t("tasks/I5_contradiction.yaml", seed_with_variant("tasks/I5_contradiction.yaml", "cancel"));
  const ScenarioContract c = contract_from_episode(t.spec, t.graph, t.model);
  ASSERT_TRUE(c.contradiction);
  sim::Data data = sim::make_data(t.model);
  ScriptDriver driver(t.spec);
  policy::NoopPolicy noop;
  RunOptions options;
  options.horizon = 2.0;
  EpisodeSetup setup;
  setup.task = t.spec.task;
  setup.policy = "noop";
  const EpisodeLog log = run_episode(t.model, data, noop, driver, setup, options);
  ASSERT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
  EXPECT_EQ(c.contradiction_event, "wave_off.start");
  EXPECT_EQ(c.success_predicate, "intent");
  const size_t success = *log.predicate_index("success");
  const size_t intent = *log.predicate_index("intent");
  EXPECT_EQ(log.steps.back().predicates[success], 1);
  EXPECT_EQ(log.steps.back().predicates[intent], 0);
  const EpisodeMetrics m = compute_metrics(c, log, MetricConstants{});
  EXPECT_FALSE(m.cir.has_value());
  EXPECT_FALSE(m.success);
}

TEST_F(ScriptContractEpisode, UnknownHumanPartIsAnInputError) {
  Task t("tasks/C1_handover_h2r.yaml");
  t.spec.safety.contact_permitted[0].human = script::Text("right.tail");
  try {
    contract_from_episode(t.spec, t.graph, t.model);
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "safety.contact_permitted[0].human: expected SIDE.REGION naming body capsules, got 'right.tail'");
  }
}

}  // namespace
}  // namespace hribench::eval
