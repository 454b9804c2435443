// The expert's plan read from the real task scripts: the steps of each competence level, what
// they wait for, and what drops them.

#include "policy/oracle_plan.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/errors.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::policy {
namespace {

script::EpisodeSpec episode(const std::string& file, uint64_t seed) {
  return script::sample(script::load_scenario(file), seed);
}

// The first seed (from 0) whose sampled variant is `variant`.
script::EpisodeSpec episode_of_variant(const std::string& file, const std::string& variant) {
  const script::Scenario scenario = script::load_scenario(file);
  for (uint64_t seed = 0; seed < 200; ++seed) {
    script::EpisodeSpec spec = script::sample(scenario, seed);
    if (spec.variant == variant) return spec;
  }
  ADD_FAILURE() << "no seed of " << file << " samples " << variant;
  return {};
}

TEST(OraclePlan, PointPickWaitsForTheStrokeExceptBlind) {
  const script::EpisodeSpec spec = episode("tasks/I1_point_pick.yaml", 0);
  for (Competence c : {Competence::kOracle, Competence::kReactive, Competence::kBlind}) {
    const std::vector<PlanStep> plan = make_plan(spec, c);
    ASSERT_EQ(plan.size(), 1u) << to_string(c);
    EXPECT_EQ(plan[0].act, "put");
    EXPECT_EQ(plan[0].kind, StepKind::kPlace);
    EXPECT_EQ(plan[0].target, "bin");
    EXPECT_EQ(plan[0].after, c == Competence::kBlind ? "" : "point.stroke") << to_string(c);
  }
}

TEST(OraclePlan, ContradictionDropsDeliverForTheOracleOnly) {
  const script::EpisodeSpec spec = episode_of_variant("tasks/I5_contradiction.yaml", "cancel");
  const std::vector<PlanStep> oracle = make_plan(spec, Competence::kOracle);
  ASSERT_EQ(oracle.size(), 4u);
  EXPECT_EQ(oracle[0].kind, StepKind::kPick);
  EXPECT_EQ(oracle[1].kind, StepKind::kPutBack);
  EXPECT_EQ(oracle[1].after, "wave_off.gesture");
  EXPECT_EQ(oracle[2].kind, StepKind::kHome);
  EXPECT_EQ(oracle[3].act, "deliver");
  EXPECT_EQ(oracle[3].dropped_by, "wave_off.gesture");
  EXPECT_EQ(oracle[3].pause_on, "wave_off.start");
  // The baselines keep the original instruction: fetch and deliver, never dropped.
  for (Competence c : {Competence::kReactive, Competence::kBlind}) {
    const std::vector<PlanStep> plan = make_plan(spec, c);
    ASSERT_EQ(plan.size(), 2u) << to_string(c);
    EXPECT_EQ(plan[1].act, "deliver");
    EXPECT_EQ(plan[1].target, "plate");
    EXPECT_TRUE(plan[1].dropped_by.empty());
  }
}

TEST(OraclePlan, SomeoneElsePlacesHasANominalPlanAndAStandDown) {
  const script::EpisodeSpec spec = episode_of_variant("tasks/X3_someone_else_places.yaml", "same_object");
  const std::vector<PlanStep> oracle = make_plan(spec, Competence::kOracle);
  ASSERT_EQ(oracle.size(), 3u);
  EXPECT_EQ(oracle[0].kind, StepKind::kPick);
  EXPECT_EQ(oracle[0].object, "item");
  EXPECT_TRUE(oracle[0].act.empty());
  EXPECT_EQ(oracle[0].dropped_by, "do_it.reach");
  EXPECT_EQ(oracle[1].kind, StepKind::kPlace);
  EXPECT_EQ(oracle[1].target, "plate");
  EXPECT_EQ(oracle[2].kind, StepKind::kHome);
  EXPECT_EQ(oracle[2].after, "do_it.reach");
  // Reactive never stands down and keeps going.
  const std::vector<PlanStep> reactive = make_plan(spec, Competence::kReactive);
  ASSERT_EQ(reactive.size(), 2u);
  EXPECT_TRUE(reactive[1].dropped_by.empty());
}

TEST(OraclePlan, BlockedTargetWaitsForTheRetractOnlyForTheOracle) {
  const script::EpisodeSpec spec = episode_of_variant("tasks/X4_blocked_target.yaml", "hand_block");
  const std::vector<PlanStep> oracle = make_plan(spec, Competence::kOracle);
  ASSERT_EQ(oracle.size(), 3u);
  EXPECT_EQ(oracle[1].kind, StepKind::kHover);
  EXPECT_DOUBLE_EQ(oracle[1].distance, 0.30);
  EXPECT_EQ(oracle[2].after, "block.retract");
  EXPECT_EQ(make_plan(spec, Competence::kReactive)[2].after, "");
}

TEST(OraclePlan, HandoverGoalsBecomeOfferAndRelease) {
  const script::EpisodeSpec spec = episode("tasks/C2_handover_r2h.yaml", 0);
  const std::vector<PlanStep> plan = make_plan(spec, Competence::kOracle);
  ASSERT_EQ(plan.size(), 3u);
  EXPECT_EQ(plan[1].kind, StepKind::kOffer);
  EXPECT_EQ(plan[2].kind, StepKind::kRelease);
  EXPECT_EQ(plan[2].after, "take.close");
  EXPECT_EQ(plan[2].target.rfind("human.", 0), 0u);
}

TEST(OraclePlan, UnknownGoalFormIsAnInputErrorNamingTheAct) {
  script::EpisodeSpec spec = episode("tasks/I1_point_pick.yaml", 0);
  for (auto& entry : spec.acts) {
    if (entry.name == "put") entry.value.goal->source = "moved(bin, 0.1)";
  }
  try {
    make_plan(spec, Competence::kOracle);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(),
                 "act put: expected a goal the expert knows (grasped, in, on, near, held, at_home, "
                 "still), got 'moved(bin, 0.1)'");
  }
}

}  // namespace
}  // namespace hribench::policy
