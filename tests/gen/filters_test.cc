#include "gen/filters.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "core/errors.h"
#include "gen/pool.h"
#include "policy/builtin.h"
#include "policy/registry.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::gen {
namespace {

using ::testing::HasSubstr;

// A validated point_pick candidate (the filters' "pass" case); each test breaks one thing.
script::EpisodeSpec point_pick() {
  static const script::Scenario scenario = script::load_scenario("tasks/I1_point_pick.yaml");
  return script::sample(scenario, candidate_seed(0, "point_pick", 0));
}

script::Entry<script::SceneObject>& object(script::EpisodeSpec& spec, const std::string& name) {
  for (auto& e : spec.scene.objects) {
    if (e.name == name) return e;
  }
  throw std::runtime_error("no object " + name);
}

std::string target_of(const script::EpisodeSpec& spec) {
  for (const auto& v : spec.vars) {
    if (v.name == "target") return v.value.expr.text;
  }
  return "";
}

TEST(Filters, NamesRoundTrip) {
  for (const Filter f : kFilters) EXPECT_EQ(filter_from_name(to_string(f)), f);
  EXPECT_FALSE(filter_from_name("bogus"));
}

TEST(Filters, TheBaseCandidatePassesEveryFilter) {
  const script::EpisodeSpec spec = point_pick();
  const Verdict verdict = validate_candidate(spec, FilterOptions{"none"});
  EXPECT_TRUE(verdict.ok()) << to_string(*verdict.failed) << ": " << verdict.reason;
}

TEST(Filters, OrderingFailsWhenTheDrawnTimingsOutlastTheHorizon) {
  script::EpisodeSpec spec = point_pick();
  EXPECT_TRUE(check_ordering(spec).ok);
  spec.horizon = 1.0;  // the pointing act (onset >= 0.5 s, then >= 1.85 s of phases) cannot fit
  const FilterOutcome o = check_ordering(spec);
  EXPECT_FALSE(o.ok);
  EXPECT_THAT(o.reason, HasSubstr("after the horizon"));
  const Verdict verdict = validate_candidate(spec, FilterOptions{"none"});
  EXPECT_EQ(verdict.failed, Filter::kOrdering);
}

TEST(Filters, OrderingFailsWhenTheGraphDoesNotCompile) {
  script::EpisodeSpec spec = point_pick();
  spec.acts[1].value.after = "nowhere.stroke";
  const FilterOutcome o = check_ordering(spec);
  EXPECT_FALSE(o.ok);
  EXPECT_THAT(o.reason, HasSubstr("does not compile"));
}

TEST(Filters, SceneFailsForAnObjectOffTheTable) {
  script::EpisodeSpec spec = point_pick();
  object(spec, "obj_a").value.pose->xy = {script::Num(3.0), script::Num(0.0)};
  const Verdict verdict = validate_candidate(spec, FilterOptions{"none"});
  EXPECT_EQ(verdict.failed, Filter::kScene);
  EXPECT_THAT(verdict.reason, HasSubstr("obj_a"));
}

TEST(Filters, SuccessFailsWithoutPredicatesAndPassesWithThem) {
  script::EpisodeSpec spec = point_pick();
  {
    CandidateScene scene = make_candidate_scene(spec);
    EXPECT_TRUE(check_success(scene).ok);
  }
  spec.success.clear();
  CandidateScene scene = make_candidate_scene(spec);
  const FilterOutcome o = check_success(scene);
  EXPECT_FALSE(o.ok);
  EXPECT_EQ(o.reason, "no success predicates");
}

TEST(Filters, SuccessFailsForAPredicateOnAnUnknownObject) {
  script::EpisodeSpec spec = point_pick();
  spec.success.push_back(script::Pred{"in(ghost, bin)", {}});
  CandidateScene scene = make_candidate_scene(spec);
  const FilterOutcome o = check_success(scene);
  EXPECT_FALSE(o.ok);
  EXPECT_THAT(o.reason, HasSubstr("not evaluable"));
}

TEST(Filters, ReachableFailsForABinAtTheFarCorner) {
  script::EpisodeSpec spec = point_pick();
  {
    CandidateScene scene = make_candidate_scene(spec);
    EXPECT_TRUE(check_reachable(scene).ok) << check_reachable(scene).reason;
  }
  object(spec, "bin").value.pose->xy = {script::Num(0.92), script::Num(0.38)};
  CandidateScene scene = make_candidate_scene(spec);
  const FilterOutcome o = check_reachable(scene);
  EXPECT_FALSE(o.ok);
  EXPECT_THAT(o.reason, HasSubstr("bin (above)"));
  EXPECT_THAT(o.reason, HasSubstr("out of reach"));
}

TEST(Filters, PenetrationFailsForAPersonStandingInTheTable) {
  script::EpisodeSpec spec = point_pick();
  {
    CandidateScene scene = make_candidate_scene(spec);
    EXPECT_TRUE(check_penetration(scene).ok) << check_penetration(scene).reason;
  }
  spec.human.stand.x = script::Num(1.0);  // pelvis over the far table edge (x 1.05)
  CandidateScene scene = make_candidate_scene(spec);
  const FilterOutcome o = check_penetration(scene);
  EXPECT_FALSE(o.ok);
  EXPECT_THAT(o.reason, HasSubstr("enters the table"));
}

TEST(Filters, LabelsFailWhenTheRayMustPassThroughAnotherObject) {
  script::EpisodeSpec spec = point_pick();
  {
    const CandidateScene scene = make_candidate_scene(spec);
    EXPECT_TRUE(check_labels(scene).ok) << check_labels(scene).reason;
  }
  // The person points at the target; the label now claims another object.
  const std::string target = target_of(spec);
  const std::string other = target == "obj_a" ? "obj_c" : "obj_a";
  spec.acts[0].value.label->through = script::Text(other.c_str());
  const CandidateScene scene = make_candidate_scene(spec);
  const FilterOutcome o = check_labels(scene);
  EXPECT_FALSE(o.ok);
  EXPECT_THAT(o.reason, HasSubstr("point.label"));
}

TEST(Filters, LabelsFailForAZoneTheHandNeverReaches) {
  static const script::Scenario scenario = script::load_scenario("tasks/C1_handover_h2r.yaml");
  script::EpisodeSpec spec = script::sample(scenario, candidate_seed(0, "handover_h2r", 1));
  {
    const CandidateScene scene = make_candidate_scene(spec);
    EXPECT_TRUE(check_labels(scene).ok) << check_labels(scene).reason;
  }
  CandidateScene scene = make_candidate_scene(spec);
  for (PlannedAct& plan : scene.plans) {
    for (auto& [name, zone] : plan.params.zones) zone.center += core::Vec3(0, 0, 0.5);
  }
  const FilterOutcome o = check_labels(scene);
  EXPECT_FALSE(o.ok);
  EXPECT_THAT(o.reason, HasSubstr("offer.label"));
}

TEST(Filters, VisibilityFailsForAPersonOutsideTheImage) {
  script::EpisodeSpec spec = point_pick();
  {
    CandidateScene scene = make_candidate_scene(spec);
    EXPECT_TRUE(check_visibility(scene).ok) << check_visibility(scene).reason;
  }
  // agentview looks from (-0.4, -1.4, 2.0) toward the table: a person beside the camera is out of it.
  spec.human.stand.x = script::Num(1.3);
  spec.human.stand.y = script::Num(-2.2);
  CandidateScene scene = make_candidate_scene(spec);
  const FilterOutcome o = check_visibility(scene);
  EXPECT_FALSE(o.ok);
  EXPECT_THAT(o.reason, HasSubstr("the cue hand of point (point.stroke) is not visible in agentview: outside the image"));
}

TEST(Filters, VisibilityFailsForObjectsHiddenBehindThePerson) {
  script::EpisodeSpec spec = point_pick();
  // The person stands beside the table, between agentview and the objects.
  spec.human.stand.x = script::Num(0.55);
  spec.human.stand.y = script::Num(-0.75);
  spec.human.stand.yaw_deg = script::Num(90.0);
  CandidateScene scene = make_candidate_scene(spec);
  const FilterOutcome o = check_visibility(scene);
  EXPECT_FALSE(o.ok);
  EXPECT_THAT(o.reason, HasSubstr("is not visible in agentview: hidden behind"));
}

TEST(Filters, VisibilityFailsForAKeyObjectTooSmallAt224) {
  script::EpisodeSpec spec = point_pick();
  // The target (a 5 cm cube in this candidate) at the table's far left corner, the farthest
  // from agentview: under 5 px across at 224 x 224.
  const std::string target = target_of(spec);
  ASSERT_EQ(object(spec, target).value.kind.value(), "cube");
  object(spec, target).value.pose->xy = {script::Num(0.95), script::Num(0.42)};
  CandidateScene scene = make_candidate_scene(spec);
  const FilterOutcome outcome = check_visibility(scene);
  EXPECT_FALSE(outcome.ok);
  EXPECT_THAT(outcome.reason, ::testing::MatchesRegex(target + " is 4[.][0-9] px across in agentview at 224 px, under 5 px"));
}

TEST(Filters, VisibilityFailsForACueHandTooSmallAt224) {
  script::EpisodeSpec spec = point_pick();
  // The smallest person the model builds, standing back from the table: a hand of 4-5 cm,
  // 2.7 m from agentview.
  spec.human.height = script::Num(1.0);
  spec.human.stand.x = script::Num(1.6);
  CandidateScene scene = make_candidate_scene(spec);
  const FilterOutcome outcome = check_visibility(scene);
  EXPECT_FALSE(outcome.ok);
  EXPECT_THAT(outcome.reason, ::testing::MatchesRegex(
                                  "the cue hand of point \\(point.stroke\\) is [0-9.]+ px across in agentview at "
                                  "224 px, under 7 px"));
}

TEST(Filters, VisibilityFailsForAPointedTargetBesideAnotherObjectInTheImage) {
  script::EpisodeSpec spec = point_pick();
  {
    CandidateScene scene = make_candidate_scene(spec);
    ASSERT_TRUE(check_visibility(scene).ok) << check_visibility(scene).reason;
  }
  // Another object 6 cm behind the target along agentview's line of sight: apart on the table,
  // a few pixels apart in the image.
  const std::string target = target_of(spec);
  auto& t = object(spec, target).value;
  const double x = t.pose->xy[0].value(), y = t.pose->xy[1].value();
  const core::Vec3 sight = (core::Vec3(x, y, 0.75) - core::Vec3(-0.4, -1.4, 2.0)).normalized();
  const core::Vec3 behind = core::Vec3(x, y, 0) + 0.08 * core::Vec3(sight.x(), sight.y(), 0).normalized();
  for (auto& e : spec.scene.objects) {
    if (e.name != target && e.value.kind.value() == "cube" && !e.value.in) {
      e.value.pose->xy = {script::Num(behind.x()), script::Num(behind.y())};
      CandidateScene scene = make_candidate_scene(spec);
      const FilterOutcome outcome = check_visibility(scene);
      EXPECT_FALSE(outcome.ok);
      EXPECT_THAT(outcome.reason, ::testing::MatchesRegex("point's pointed target " + target + " is [0-9.]+ px from " +
                                                          e.name + " in agentview at 224 px, under 12 px"));
      return;
    }
  }
  FAIL() << "no other cube to move";
}

TEST(Filters, ExecutableRunsThePolicyAndNoneSkipsIt) {
  script::EpisodeSpec spec = point_pick();
  spec.horizon = 3.0;
  EXPECT_TRUE(check_executable(spec, "none").ok);
  // noop never puts the target in the bin.
  const FilterOutcome fails = check_executable(spec, "noop");
  EXPECT_FALSE(fails.ok);
  EXPECT_THAT(fails.reason, HasSubstr("noop does not succeed"));
  // With success = "nothing moved", noop succeeds.
  spec.success = {script::Pred{"not moved(bin, 0.05)", {}}};
  const FilterOutcome passes = check_executable(spec, "noop");
  EXPECT_TRUE(passes.ok) << passes.reason;
}

TEST(Filters, AtRestIsTheLastFilter) {
  EXPECT_EQ(kFilters.back(), Filter::kAtRest);
  EXPECT_EQ(to_string(Filter::kAtRest), "at_rest");
}

TEST(Filters, AtRestPassesAPersonPointingFromAcrossTheTable) {
  script::EpisodeSpec spec = point_pick();
  spec.horizon = 8.0;  // the pointing act is over by then
  const FilterOutcome o = check_at_rest(spec);
  EXPECT_TRUE(o.ok) << o.reason;
}

TEST(Filters, AtRestFailsForAPersonPressedAgainstTheRobot) {
  script::EpisodeSpec spec = point_pick();
  spec.horizon = 1.0;
  spec.human.stand.x = script::Num(0.7);  // the abdomen against the robot's hand at home
  const FilterOutcome o = check_at_rest(spec);
  EXPECT_FALSE(o.ok);
  EXPECT_THAT(o.reason, HasSubstr("the person's abdomen (torso) touches the robot at rest (hand) at 0.00 s "
                                  "before the person's first act"));
  EXPECT_THAT(o.reason, ::testing::MatchesRegex(".*, [0-9.]+ N \\(peak [0-9.]+ N\\)"));
}

TEST(Filters, AnUnknownExecutablePolicyIsBadInput) {
  const script::EpisodeSpec spec = point_pick();
  EXPECT_THROW(validate_candidate(spec, FilterOptions{"no_such_policy"}), core::InputError);
}

}  // namespace
}  // namespace hribench::gen
