#include "eval/reward.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/errors.h"
#include "eval/episode_builder.h"
#include "eval/metrics.h"

namespace hribench::eval {
namespace {

using testing::EpisodeBuilder;
using testing::human_contact;
constexpr double kTol = 1e-9;
const script::RewardWeights kDefault;
const MetricConstants kConstants;

RewardTerms at(const ScenarioContract& c, const EpisodeLog& log, double t,
               const script::RewardWeights& w = kDefault) {
  return dense_reward(c, log, static_cast<size_t>(std::lround(t / log.control_dt)), w, kConstants);
}

ScenarioContract reach_then_place() {
  ScenarioContract c;
  c.robot_acts = {{"reach", core::Vec3(1.4, 0, 1.0)}, {"place", core::Vec3(0.4, 0, 1.0)}};
  return c;
}

TEST(DenseReward, ProgressIsTheCurrentActsDistanceGained) {
  // The tool moves +x at 1 m/s from t = 1 to 2: 5 cm per step toward reach's goal.
  EpisodeBuilder b(4.0);
  b.move_x(1.0, 2.0, 1.0).event(2.0, "reach.end", EventKind::kActEnd, Actor::kRobot);
  const ScenarioContract c = reach_then_place();
  EXPECT_NEAR(at(c, b.log(), 0.5).progress, 0.0, kTol);  // still
  EXPECT_NEAR(at(c, b.log(), 1.5).progress, 0.05, kTol);
  // reach ended at 2.0: the step that ends there already counts toward place's goal (away).
  EXPECT_NEAR(at(c, b.log(), 2.0).progress, -0.05, kTol);
  script::RewardWeights w;
  w.progress = 3;
  EXPECT_NEAR(at(c, b.log(), 1.5, w).progress, 0.15, kTol);
  // 19 steps of 5 cm toward reach's goal, then the last one away from place's.
  EXPECT_NEAR(dense_return(reach_then_place(), b.log(), kDefault, kConstants).progress, 0.90, kTol);
  // No goal: no progress term.
  ScenarioContract no_goal;
  no_goal.robot_acts = {{"wave", std::nullopt}};
  EXPECT_EQ(at(no_goal, b.log(), 1.5).progress, 0.0);
}

TEST(DenseReward, SuccessBonusAtTheLastStepOfASuccessfulEpisode) {
  EpisodeBuilder b(4.0);
  b.predicate("success", 1.0, 1.5).predicate("success", 3.0, 4.0);
  const ScenarioContract c;
  const size_t last = b.log().steps.size() - 1;
  EpisodeMetrics succeeded;
  succeeded.success = true;
  // Only the episode's last step, and only when the metrics say it succeeded.
  EXPECT_EQ(at(c, b.log(), 1.0).success, 0.0);
  EXPECT_EQ(dense_reward(c, b.log(), last, kDefault, kConstants).success, 0.0);  // not ended
  EXPECT_EQ(dense_reward(c, b.log(), last, kDefault, kConstants, &succeeded).success, 10.0);
  EpisodeMetrics failed = succeeded;
  failed.success = false;  // e.g. a premature answer with the task done
  EXPECT_EQ(dense_reward(c, b.log(), last, kDefault, kConstants, &failed).success, 0.0);
  // The return scores the finished log: success held for the last 0.5 s.
  ASSERT_TRUE(compute_metrics(c, b.log(), kConstants).success);
  EXPECT_EQ(dense_return(c, b.log(), kDefault, kConstants).success, 10.0);
  EpisodeBuilder dropped(4.0);
  dropped.predicate("success", 1.0, 3.0);  // held, then lost before the end
  EXPECT_EQ(dense_return(c, dropped.log(), kDefault, kConstants).success, 0.0);
}

TEST(DenseReward, MotionBeforeTheGoCueIsPenalised) {
  EpisodeBuilder b(4.0);
  b.move_x(0.5, 3.0, 0.2).event(2.0, "go1.stroke");
  ScenarioContract c = reach_then_place();
  c.cues = {{"go1", "go1.stroke", CueKind::kGo, 1.0, core::Vec3(1.4, 0, 1.0), "reach", ""}};
  EXPECT_NEAR(at(c, b.log(), 1.0).premature_motion, -0.01, kTol);  // 1 cm in the step
  EXPECT_NEAR(at(c, b.log(), 2.0).premature_motion, -0.01, kTol);  // the cue comes at the step's end
  EXPECT_EQ(at(c, b.log(), 2.05).premature_motion, 0.0);           // cue given: allowed
  // A second go cue for the same act (after a stop): the first one already allowed motion.
  c.cues.push_back({"go2", "go2.stroke", CueKind::kGo, 1.0, core::Vec3(1.4, 0, 1.0), "reach", ""});
  b.event(3.0, "go2.stroke");
  EXPECT_EQ(at(c, b.log(), 2.5).premature_motion, 0.0);
  EXPECT_NEAR(at(c, b.log(), 1.0).premature_motion, -0.01, kTol);
  c.cues.pop_back();
  // Motion allowed from another event; another act answering the cue: no penalty.
  c.cues[0].motion_allowed_from = "episode.start";
  EXPECT_EQ(at(c, b.log(), 1.0).premature_motion, 0.0);
  c.cues[0].motion_allowed_from = "";
  c.cues[0].answered_by = "place";
  EXPECT_EQ(at(c, b.log(), 1.0).premature_motion, 0.0);
  c.cues[0].answered_by = "reach";
  // Only motion toward the goal faster than an answer's onset (response_speed, 2 cm/s) counts:
  // backing away from the goal, or drifting toward it, before the cue is no answer.
  EpisodeBuilder away(4.0);
  away.move_x(0.5, 3.0, -0.2).event(2.0, "go1.stroke");
  EXPECT_EQ(at(c, away.log(), 1.0).premature_motion, 0.0);
  EpisodeBuilder drift(4.0);
  drift.move_x(0.5, 3.0, 0.015).event(2.0, "go1.stroke");
  EXPECT_EQ(at(c, drift.log(), 1.0).premature_motion, 0.0);
}

TEST(DenseReward, SeparationViolationCostsItsDuration) {
  EpisodeBuilder b(4.0);
  b.separation(1.0, 2.0, 0.05, 0.5, 0.5).separation(3.0, 4.0, 0.9, 0.0, 0.0);
  const ScenarioContract c;
  EXPECT_NEAR(at(c, b.log(), 1.5).separation, -0.05, kTol);  // 5 cm at 0.5 m/s: inside S_p
  EXPECT_EQ(at(c, b.log(), 3.5).separation, 0.0);             // far and still
  EXPECT_EQ(at(c, b.log(), 0.5).separation, 0.0);             // nobody near
  // In a permitted contact phase only fast motion that close counts.
  ScenarioContract handover;
  handover.permitted_contacts = {{true, {}, {"offer.hold_stable", "take.end"}}};
  b.event(0.5, "offer.hold_stable");
  EXPECT_NEAR(at(handover, b.log(), 1.5).separation, -0.05, kTol);  // 0.5 m/s > 0.25 m/s
  EpisodeBuilder slow(4.0);
  slow.separation(1.0, 2.0, 0.05, 0.1, 0.1).event(0.5, "offer.hold_stable");
  EXPECT_EQ(at(handover, slow.log(), 1.5).separation, 0.0);
  EXPECT_NEAR(at(ScenarioContract{}, slow.log(), 1.5).separation, -0.05, kTol);
}

TEST(DenseReward, ContactIsGradedByBodyRegion) {
  EXPECT_DOUBLE_EQ(contact_grade(human::BodyRegion::kHead), 1.0);
  EXPECT_DOUBLE_EQ(contact_grade(human::BodyRegion::kThigh), 130.0 / 220.0);
  EpisodeBuilder b(4.0);
  b.contact(1.0, 1.0, human_contact("head", human::BodyRegion::kHead, 20.0, false))
      .contact(2.0, 2.0, human_contact("right_thigh", human::BodyRegion::kThigh, 20.0, false))
      .contact(3.0, 3.0, human_contact("right_hand", human::BodyRegion::kHand, 5.0, true));
  ScenarioContract c;
  EXPECT_NEAR(at(c, b.log(), 1.0).contact, -0.05, kTol);
  EXPECT_NEAR(at(c, b.log(), 2.0).contact, -0.05 * 130.0 / 220.0, kTol);
  EXPECT_NEAR(at(c, b.log(), 3.0).contact, -0.05 * 130.0 / 140.0, kTol);
  // A finger touching the hand in a permitted phase is no penalty; an arm link still is.
  c.permitted_contacts = {{true, {"right_hand"}, {"episode.start", ""}}};
  EXPECT_EQ(at(c, b.log(), 3.0).contact, 0.0);
  EXPECT_NEAR(at(c, b.log(), 1.0).contact, -0.05, kTol);
  script::RewardWeights w;
  w.contact = 0;
  EXPECT_EQ(at(c, b.log(), 1.0, w).contact, 0.0);
}

TEST(DenseReward, StepZeroHasNoReward) {
  EpisodeBuilder b(1.0);
  EXPECT_DEATH(dense_reward(ScenarioContract{}, b.log(), 0, kDefault, kConstants), "check failed");
}

}  // namespace
}  // namespace hribench::eval
