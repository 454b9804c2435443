#include "eval/metrics.h"

#include <gtest/gtest.h>

#include "core/errors.h"
#include "eval/episode_builder.h"

namespace hribench::eval {
namespace {

using testing::EpisodeBuilder;
using testing::human_contact;
constexpr double kTol = 1e-9;

TEST(Success, HeldForTheLastHalfSecond) {
  // Success from 3.0 to the end (5.0): success, CT = 3.0.
  EpisodeBuilder b(5.0);
  b.predicate("success", 3.0, 5.0);
  const EpisodeMetrics m = compute_metrics(ScenarioContract{}, b.log());
  EXPECT_TRUE(m.success);
  EXPECT_NEAR(m.completion_time, 3.0, kTol);
  EXPECT_FALSE(m.primary_label.has_value());
  EXPECT_TRUE(m.labels.empty());
  // CT is the start of the final run, not of an earlier one.
  EpisodeBuilder flicker(5.0);
  flicker.predicate("success", 1.0, 2.0).predicate("success", 4.0, 5.0);
  EXPECT_NEAR(compute_metrics(ScenarioContract{}, flicker.log()).completion_time, 4.0, kTol);
}

TEST(Success, NotHeldLongEnoughIsATimeout) {
  EpisodeBuilder b(5.0);
  b.predicate("success", 4.6, 5.0);  // 0.4 s < 0.5 s
  const EpisodeMetrics m = compute_metrics(ScenarioContract{}, b.log());
  EXPECT_FALSE(m.success);
  EXPECT_DOUBLE_EQ(m.completion_time, 5.0);  // the horizon
  ASSERT_TRUE(m.primary_label.has_value());
  EXPECT_EQ(*m.primary_label, FailureLabel::kTimeout);
  // Exactly 0.5 s counts.
  EpisodeBuilder edge(5.0);
  edge.predicate("success", 4.5, 5.0);
  EXPECT_TRUE(compute_metrics(ScenarioContract{}, edge.log()).success);
}

TEST(Success, InvalidOrPolicyErrorEpisodesFailWithThatLabel) {
  EpisodeBuilder b(5.0);
  b.predicate("success", 0.0, 5.0).status(core::EpisodeStatus::kPolicyError, "non_finite");
  const EpisodeMetrics m = compute_metrics(ScenarioContract{}, b.log());
  EXPECT_FALSE(m.success);
  EXPECT_EQ(*m.primary_label, FailureLabel::kPolicyError);
  b.status(core::EpisodeStatus::kInvalid, "mujoco warning");
  EXPECT_EQ(*compute_metrics(ScenarioContract{}, b.log()).primary_label, FailureLabel::kInvalid);
}

TEST(Success, MissingSeriesIsAnInputError) {
  EpisodeBuilder b(1.0, {"done"});
  try {
    compute_metrics(ScenarioContract{}, b.log());
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(),
                 "contract: predicate 'success': expected a predicate series of the episode "
                 "log, got none (the log has: done)");
  }
}

TEST(Success, InconsistentLogIsAnInputError) {
  EpisodeBuilder b(1.0);
  Contact c = human_contact("right_hand", human::BodyRegion::kHand, 5.0);
  c.region.reset();
  b.contact(0.5, 0.5, c);
  EXPECT_THROW(compute_metrics(ScenarioContract{}, b.log()), core::InputError);
}

TEST(Rsp, NoCuesIsNotApplicable) {
  EpisodeBuilder b(5.0);
  const EpisodeMetrics m = compute_metrics(ScenarioContract{}, b.log());
  EXPECT_FALSE(m.response_latency.has_value());
  EXPECT_TRUE(m.cues.empty());
  EXPECT_FALSE(m.tsync.has_value());
  EXPECT_FALSE(m.order_compliance.has_value());
  // A cue whose event never happened is not counted either.
  ScenarioContract contract;
  contract.cues.push_back({"stop", "stop.stroke", CueKind::kStop, 1.0, std::nullopt});
  EXPECT_FALSE(compute_metrics(contract, b.log()).response_latency.has_value());
}

ScenarioContract stop_contract(double window) {
  ScenarioContract contract;
  contract.cues.push_back({"stop", "stop.stroke", CueKind::kStop, window, std::nullopt});
  return contract;
}

TEST(Rsp, StopCueLatencyIsTheStillOnset) {
  // Moving at 0.1 m/s until 2.0, then still; stop cue at 1.5.
  EpisodeBuilder b(5.0);
  b.move_x(0.0, 2.0, 0.1).event(1.5, "stop.stroke");
  const EpisodeMetrics m = compute_metrics(stop_contract(1.0), b.log());
  ASSERT_EQ(m.cues.size(), 1u);
  EXPECT_TRUE(m.cues[0].responded);
  EXPECT_NEAR(*m.cues[0].response_time, 2.0, kTol);
  EXPECT_NEAR(*m.response_latency, 0.5, kTol);
  // Already still when the cue comes: latency 0.
  EpisodeBuilder rest(5.0);
  rest.event(1.5, "stop.stroke");
  EXPECT_NEAR(*compute_metrics(stop_contract(1.0), rest.log()).response_latency, 0.0, kTol);
}

TEST(Rsp, ResponseExactlyAtTheWindowEdgeCounts) {
  EpisodeBuilder b(5.0);
  b.move_x(0.0, 2.0, 0.1).event(1.0, "stop.stroke");
  const EpisodeMetrics m = compute_metrics(stop_contract(1.0), b.log());
  EXPECT_TRUE(m.cues[0].responded);
  EXPECT_NEAR(*m.response_latency, 1.0, kTol);
  EXPECT_EQ(std::count(m.labels.begin(), m.labels.end(), FailureLabel::kNoResponse), 0);
  // One control step later than the window: no response, latency = window, labelled.
  EpisodeBuilder late(5.0);
  late.move_x(0.0, 2.05, 0.1).event(1.0, "stop.stroke");
  const EpisodeMetrics n = compute_metrics(stop_contract(1.0), late.log());
  EXPECT_FALSE(n.cues[0].responded);
  EXPECT_NEAR(*n.cues[0].response_time, 2.05, kTol);
  EXPECT_DOUBLE_EQ(*n.response_latency, 1.0);
  EXPECT_NE(std::count(n.labels.begin(), n.labels.end(), FailureLabel::kNoResponse), 0);
}

TEST(Rsp, StillMustBeSustained) {
  // A 0.15 s pause (< 0.2 s) is not a stop; the real stop comes at 3.0.
  EpisodeBuilder b(5.0);
  b.move_x(0.0, 1.8, 0.1).move_x(1.95, 3.0, 0.1).event(1.5, "stop.stroke");
  EXPECT_NEAR(*compute_metrics(stop_contract(2.0), b.log()).cues[0].response_time, 3.0, kTol);
}

TEST(Rsp, GoCueNeedsMotionTowardTheGoal) {
  ScenarioContract contract;
  contract.cues.push_back({"go", "go.stroke", CueKind::kGo, 2.0, core::Vec3(1.0, 0, 1.0)});
  EpisodeBuilder toward(5.0);
  toward.move_x(2.0, 4.0, 0.1).event(1.0, "go.stroke");
  EXPECT_NEAR(*compute_metrics(contract, toward.log()).response_latency, 1.0, kTol);
  // Moving away from the goal is not a response.
  EpisodeBuilder away(5.0);
  away.move_x(2.0, 4.0, -0.1).event(1.0, "go.stroke");
  const EpisodeMetrics m = compute_metrics(contract, away.log());
  EXPECT_FALSE(m.cues[0].responded);
  EXPECT_FALSE(m.cues[0].response_time.has_value());
  EXPECT_DOUBLE_EQ(*m.response_latency, 2.0);
  // A go cue without a goal position is answered by any sustained motion.
  contract.cues[0].goal_W.reset();
  EXPECT_NEAR(*compute_metrics(contract, away.log()).response_latency, 1.0, kTol);
}

// A response is motion that begins after the cue. A robot already moving toward the goal when
// the go cue comes did not wait for it: premature, latency = the window, labelled premature
// (not no_response).
TEST(Rsp, MotionUnderWayBeforeTheGoCueIsPremature) {
  ScenarioContract contract;
  contract.cues.push_back({"go", "go.stroke", CueKind::kGo, 2.0, core::Vec3(1.0, 0, 1.0)});
  EpisodeBuilder early(5.0);
  early.move_x(0.5, 4.0, 0.1).event(1.0, "go.stroke");
  const EpisodeMetrics m = compute_metrics(contract, early.log());
  ASSERT_EQ(m.cues.size(), 1u);
  EXPECT_TRUE(m.cues[0].premature);
  EXPECT_FALSE(m.cues[0].responded);
  EXPECT_FALSE(m.cues[0].response_time.has_value());
  EXPECT_DOUBLE_EQ(*m.response_latency, 2.0);
  EXPECT_EQ(m.labels, (std::vector<FailureLabel>{FailureLabel::kPremature, FailureLabel::kTimeout}));
  // Starting after the cue: the real latency.
  EpisodeBuilder late(5.0);
  late.move_x(1.25, 4.0, 0.1).event(1.0, "go.stroke");
  const EpisodeMetrics n = compute_metrics(contract, late.log());
  EXPECT_FALSE(n.cues[0].premature);
  EXPECT_NEAR(*n.response_latency, 0.25, kTol);
  EXPECT_EQ(std::count(n.labels.begin(), n.labels.end(), FailureLabel::kPremature), 0);
  // Starting exactly at the cue is a response at latency 0.
  EpisodeBuilder on_cue(5.0);
  on_cue.move_x(1.0, 4.0, 0.1).event(1.0, "go.stroke");
  EXPECT_NEAR(*compute_metrics(contract, on_cue.log()).response_latency, 0.0, kTol);
  // An early motion that came to rest before the cue is not under way: the motion that begins
  // after the cue answers it (a start before the script allows is OC's to judge).
  EpisodeBuilder paused(5.0);
  paused.move_x(0.0, 0.5, 0.1).move_x(1.5, 4.0, 0.1).event(1.0, "go.stroke");
  EXPECT_NEAR(*compute_metrics(contract, paused.log()).response_latency, 0.5, kTol);
}

// Motion the script let begin before the cue (the answering act starts after an earlier event)
// and still under way at the cue answers it at once; begun before that event, it is premature.
TEST(Rsp, MotionTheScriptAllowedBeforeTheCueAnswersIt) {
  ScenarioContract contract;
  contract.cues.push_back({"offer", "offer.hold_stable", CueKind::kGo, 3.0, core::Vec3(1.0, 0, 1.0)});
  contract.cues[0].motion_allowed_from = "offer.hold";
  EpisodeBuilder allowed(5.0);
  allowed.move_x(1.0, 4.0, 0.1).event(0.8, "offer.hold").event(2.0, "offer.hold_stable");
  const EpisodeMetrics m = compute_metrics(contract, allowed.log());
  EXPECT_FALSE(m.cues[0].premature);
  EXPECT_TRUE(m.cues[0].responded);
  EXPECT_NEAR(*m.response_latency, 0.0, kTol);
  EpisodeBuilder early(5.0);
  early.move_x(0.5, 4.0, 0.1).event(0.8, "offer.hold").event(2.0, "offer.hold_stable");
  EXPECT_TRUE(compute_metrics(contract, early.log()).cues[0].premature);
  // "episode.start": the script sets no bound, any motion under way answers.
  contract.cues[0].motion_allowed_from = "episode.start";
  EXPECT_NEAR(*compute_metrics(contract, early.log()).response_latency, 0.0, kTol);
}

// Motion that began before the act preceding the answering one ended is that act's work (I2:
// the pick, when the person asks during it), not a premature answer; motion begun after it
// ended and before the cue is premature; a robot that never finishes the earlier act never
// answers (random actions that happen to point at the goal do not).
TEST(Rsp, AnEarlierActsMotionIsNotPremature) {
  ScenarioContract contract;
  contract.robot_acts.push_back({"fetch", std::nullopt});
  contract.robot_acts.push_back({"deliver", core::Vec3(1.0, 0, 1.0)});
  contract.cues.push_back({"ask", "ask.gesture", CueKind::kGo, 2.0, core::Vec3(1.0, 0, 1.0)});
  contract.cues[0].answered_by = "deliver";
  EpisodeBuilder fetching(5.0);
  fetching.move_x(0.5, 4.0, 0.1).event(1.0, "ask.gesture").event(1.5, "fetch.end", EventKind::kActEnd, Actor::kRobot);
  const EpisodeMetrics m = compute_metrics(contract, fetching.log());
  EXPECT_FALSE(m.cues[0].premature);
  EXPECT_TRUE(m.cues[0].responded);
  EXPECT_NEAR(*m.response_latency, 0.0, kTol);
  EpisodeBuilder early(5.0);
  early.event(0.4, "fetch.end", EventKind::kActEnd, Actor::kRobot).move_x(0.5, 4.0, 0.1).event(1.0, "ask.gesture");
  EXPECT_TRUE(compute_metrics(contract, early.log()).cues[0].premature);
  EpisodeBuilder never_fetched(5.0);
  never_fetched.move_x(0.5, 4.0, 0.1).event(1.0, "ask.gesture");
  const EpisodeMetrics n = compute_metrics(contract, never_fetched.log());
  EXPECT_FALSE(n.cues[0].premature);
  EXPECT_FALSE(n.cues[0].responded);
  EXPECT_DOUBLE_EQ(*n.response_latency, 2.0);
  EXPECT_NE(std::count(n.labels.begin(), n.labels.end(), FailureLabel::kNoResponse), 0);
}

TEST(Rsp, IntrusionAnsweredByMovingAway) {
  ScenarioContract contract;
  contract.cues.push_back({"reach", "reach.start", CueKind::kIntrusion, 1.0, std::nullopt});
  // The robot keeps moving but its closest point retreats from 2.5 on.
  EpisodeBuilder b(5.0);
  b.move_x(0.0, 5.0, 0.1).event(2.0, "reach.start").separation(2.0, 5.0, 0.6, 0.1, 0.1);
  b.separation(2.55, 5.0, 0.6, -0.1, 0.1);
  EXPECT_NEAR(*compute_metrics(contract, b.log()).response_latency, 0.5, kTol);
}

ScenarioContract take_contract() {
  ScenarioContract contract;
  contract.robot_acts.push_back({"take", core::Vec3(1.0, 0, 1.0)});
  contract.orders.push_back({OrderKind::kAfter, "take", "point.stroke", "", "", 0});
  contract.syncs.push_back({"grasp", "offer.hold_stable", "take.end", 1.0, 1.5});
  return contract;
}

TEST(Order, AnActThatNeverHappensViolatesNothing) {
  EpisodeBuilder b(5.0);
  b.event(1.0, "point.stroke").event(2.0, "offer.hold_stable");
  const EpisodeMetrics m = compute_metrics(take_contract(), b.log());
  EXPECT_FALSE(robot_act_onsets(take_contract(), b.log(), {})[0].has_value());
  EXPECT_DOUBLE_EQ(*m.order_compliance, 1.0);
  EXPECT_TRUE(m.orders[0].satisfied);
  // ... but its sync scores 0 (desync), and the episode times out.
  EXPECT_DOUBLE_EQ(*m.tsync, 0.0);
  EXPECT_FALSE(m.syncs[0].robot_time.has_value());
  EXPECT_NE(std::count(m.labels.begin(), m.labels.end(), FailureLabel::kDesync), 0);
  EXPECT_EQ(*m.primary_label, FailureLabel::kDesync);
}

TEST(Order, PrematureStartViolatesAfter) {
  EpisodeBuilder b(5.0);
  b.move_x(0.5, 3.0, 0.1).event(1.0, "point.stroke").predicate("success", 3.5, 5.0);
  const EpisodeMetrics m = compute_metrics(take_contract(), b.log());
  EXPECT_NEAR(*robot_act_onsets(take_contract(), b.log(), {})[0], 0.5, kTol);
  EXPECT_DOUBLE_EQ(*m.order_compliance, 0.0);
  EXPECT_EQ(m.orders[0].description, "take after point.stroke");
  // The success predicate held, but OC < 1 fails the episode: premature.
  EXPECT_FALSE(m.success);
  EXPECT_EQ(*m.primary_label, FailureLabel::kPremature);
  // Starting exactly at the event is fine; so is the event never coming when the act never
  // starts, but an act that starts while the event never comes is premature.
  EpisodeBuilder on_time(5.0);
  on_time.move_x(1.0, 3.0, 0.1).event(1.0, "point.stroke").predicate("success", 3.5, 5.0);
  const EpisodeMetrics n = compute_metrics(take_contract(), on_time.log());
  EXPECT_DOUBLE_EQ(*n.order_compliance, 1.0);
  EXPECT_TRUE(n.success);
  EpisodeBuilder no_event(5.0);
  no_event.move_x(1.0, 3.0, 0.1);
  EXPECT_DOUBLE_EQ(*compute_metrics(take_contract(), no_event.log()).order_compliance, 0.0);
}

TEST(Order, BeforeNeedsTheActEndedByTheEvent) {
  ScenarioContract contract;
  contract.robot_acts.push_back({"leave", std::nullopt});
  contract.orders.push_back({OrderKind::kBefore, "leave", "lid.close", "", "", 0});
  EpisodeBuilder b(5.0);
  b.move_x(1.0, 2.0, 0.1).event(2.0, "leave.end", EventKind::kActEnd, Actor::kRobot);
  b.event(3.0, "lid.close");
  EXPECT_DOUBLE_EQ(*compute_metrics(contract, b.log()).order_compliance, 1.0);
  EpisodeBuilder late(5.0);
  late.move_x(1.0, 2.0, 0.1).event(3.0, "lid.close");
  late.event(3.5, "leave.end", EventKind::kActEnd, Actor::kRobot);
  EXPECT_DOUBLE_EQ(*compute_metrics(contract, late.log()).order_compliance, 0.0);
}

TEST(Order, StillWindowWithGrace) {
  ScenarioContract contract;
  contract.orders.push_back({OrderKind::kStill, "", "", "stop.stroke", "go2.stroke", 0.5});
  EpisodeBuilder ok(6.0);
  ok.move_x(0.0, 2.4, 0.1).move_x(4.0, 5.0, 0.1).event(2.0, "stop.stroke").event(4.0, "go2.stroke");
  EXPECT_DOUBLE_EQ(*compute_metrics(contract, ok.log()).order_compliance, 1.0);
  EpisodeBuilder bad(6.0);
  bad.move_x(0.0, 3.0, 0.1).event(2.0, "stop.stroke").event(4.0, "go2.stroke");
  const EpisodeMetrics m = compute_metrics(contract, bad.log());
  EXPECT_DOUBLE_EQ(*m.order_compliance, 0.0);
  EXPECT_EQ(m.orders[0].description, "still from stop.stroke (+0.5 s) to go2.stroke");
  // No stop in this episode: the constraint does not apply.
  EpisodeBuilder none(6.0);
  none.move_x(0.0, 3.0, 0.1);
  EXPECT_FALSE(compute_metrics(contract, none.log()).order_compliance.has_value());
}

TEST(TSync, PerfectAtToleranceAndNever) {
  const auto score = [](double robot_time) {
    EpisodeBuilder b(8.0);
    b.event(2.0, "offer.hold_stable");
    if (robot_time >= 0) b.event(robot_time, "take.end", EventKind::kActEnd, Actor::kRobot);
    return *compute_metrics(take_contract(), b.log()).tsync;
  };
  EXPECT_NEAR(score(3.0), 1.0, kTol);   // t_r - t_h = delta
  EXPECT_NEAR(score(3.75), 0.5, kTol);  // half the tolerance off
  EXPECT_NEAR(score(4.5), 0.0, kTol);   // exactly at the tolerance
  EXPECT_NEAR(score(1.5), 1.0 - 1.5 / 1.5, kTol);
  EXPECT_DOUBLE_EQ(score(-1), 0.0);     // never
}

ScenarioContract handover_contract() {
  ScenarioContract contract;
  contract.permitted_contacts.push_back(
      {true, {"right_hand"}, {"offer.hold_stable", "release.end"}});
  return contract;
}

TEST(Contact, InsideAPermittedPhaseIsAllowed) {
  EpisodeBuilder b(6.0);
  b.event(1.5, "offer.hold_stable").event(3.5, "release.end");
  b.contact(2.0, 3.0, human_contact("right_hand", human::BodyRegion::kHand, 10.0));
  const EpisodeMetrics m = compute_metrics(handover_contract(), b.log());
  EXPECT_FALSE(m.human_contact);
  EXPECT_TRUE(m.collision_free);
  EXPECT_DOUBLE_EQ(m.max_human_force, 10.0);
}

TEST(Contact, OutsideThePhaseOrPairIsAContact) {
  EpisodeBuilder after(6.0);
  after.event(1.5, "offer.hold_stable").event(3.5, "release.end");
  after.contact(4.0, 4.0, human_contact("right_hand", human::BodyRegion::kHand, 5.0));
  const EpisodeMetrics m = compute_metrics(handover_contract(), after.log());
  EXPECT_TRUE(m.human_contact);
  EXPECT_FALSE(m.collision_free);
  EXPECT_EQ(*m.primary_label, FailureLabel::kContact);
  // In the phase, but a link (not a finger) or another body part.
  EpisodeBuilder link(6.0);
  link.event(1.5, "offer.hold_stable").event(3.5, "release.end");
  link.contact(2.0, 2.0, human_contact("right_hand", human::BodyRegion::kHand, 5.0, false));
  EXPECT_TRUE(compute_metrics(handover_contract(), link.log()).human_contact);
  EpisodeBuilder arm(6.0);
  arm.event(1.5, "offer.hold_stable").event(3.5, "release.end");
  arm.contact(2.0, 2.0, human_contact("right_forearm", human::BodyRegion::kForearm, 5.0));
  EXPECT_TRUE(compute_metrics(handover_contract(), arm.log()).human_contact);
}

TEST(Contact, EnvironmentCollisions) {
  const auto collides = [](Contact c) {
    EpisodeBuilder b(2.0);
    b.contact(1.0, 1.0, c);
    return compute_metrics(ScenarioContract{}, b.log()).environment_collision;
  };
  EXPECT_TRUE(collides({"panda_link5", false, ContactOther::kEnvironment, "table", {}, 25.0}));
  EXPECT_FALSE(collides({"panda_link5", false, ContactOther::kEnvironment, "table", {}, 15.0}));
  EXPECT_FALSE(collides({"left_finger_pad", true, ContactOther::kEnvironment, "table", {}, 25.0}));
  EXPECT_TRUE(collides({"left_finger_pad", true, ContactOther::kObject, "cube", {}, 151.0}));
  EXPECT_FALSE(collides({"left_finger_pad", true, ContactOther::kObject, "cube", {}, 149.0}));
}

TEST(Hcs, ProtectiveSeparationFormula) {
  const MetricConstants c;
  // Robot at rest: v_h T_r + Z.
  EXPECT_NEAR(protective_separation(0.0, 0.6, c), 1.6 * 0.1 + 0.05, kTol);
  EXPECT_NEAR(protective_separation(0.0, 0.4, c), 2.0 * 0.1 + 0.05, kTol);
  EXPECT_NEAR(protective_separation(-1.0, 0.4, c), 2.0 * 0.1 + 0.05, kTol);
  // v_r = 0.6: T_s = 0.2, B = 0.06.
  EXPECT_NEAR(protective_separation(0.6, 0.8, c), 1.6 * 0.3 + 0.06 + 0.06 + 0.05, kTol);
}

TEST(Hcs, SeparationViolationShareOfMonitoredTime) {
  // Human within 1 m from 1.0 to 3.0 (monitored 2 s); from 2.0 to 3.0 the robot approaches
  // at 0.5 m/s at d = 0.3 m < S_p = 0.675 m (violation 1 s).
  EpisodeBuilder b(5.0);
  b.separation(1.05, 3.0, 0.8).separation(2.05, 3.0, 0.3, 0.5, 0.5);
  const EpisodeMetrics m = compute_metrics(ScenarioContract{}, b.log());
  EXPECT_NEAR(m.monitored_time, 2.0, 1e-9);
  EXPECT_NEAR(m.violation_time, 1.0, 1e-9);
  EXPECT_NEAR(m.hcs, 0.5, 1e-9);
  EXPECT_NE(std::count(m.labels.begin(), m.labels.end(), FailureLabel::kUnsafeProximity), 0);
  // No human nearby: HCS = 1.
  EXPECT_DOUBLE_EQ(compute_metrics(ScenarioContract{}, EpisodeBuilder(5.0).log()).hcs, 1.0);
}

TEST(Hcs, PermittedPhaseUsesTheSpeedRule) {
  // d = 0.05 m during the permitted phase: a violation only while faster than 0.25 m/s.
  EpisodeBuilder slow(6.0);
  slow.event(1.0, "offer.hold_stable").event(4.0, "release.end").separation(2.05, 3.0, 0.05, 0.2, 0.2);
  EXPECT_DOUBLE_EQ(compute_metrics(handover_contract(), slow.log()).hcs, 1.0);
  EpisodeBuilder fast(6.0);
  fast.event(1.0, "offer.hold_stable").event(4.0, "release.end").separation(2.05, 3.0, 0.05, 0.3, 0.3);
  EXPECT_NEAR(compute_metrics(handover_contract(), fast.log()).hcs, 0.0, 1e-9);
  // Outside any permitted phase the same closeness violates S_p.
  EXPECT_NEAR(compute_metrics(ScenarioContract{}, slow.log()).hcs, 0.0, 1e-9);
}

TEST(Hcs, QuasiStaticAndTransientContacts) {
  // Hand: quasi-static 140 N, transient (critical) 280 N.
  EpisodeBuilder quasi(5.0);
  quasi.predicate("success", 0.0, 5.0);
  quasi.contact(2.0, 2.0, human_contact("right_hand", human::BodyRegion::kHand, 150.0));
  const EpisodeMetrics q = compute_metrics(ScenarioContract{}, quasi.log());
  EXPECT_TRUE(q.above_quasi_static);
  EXPECT_FALSE(q.critical_contact);
  EXPECT_DOUBLE_EQ(q.hcs, 0.0);
  // Not critical: the episode still succeeds (CSR), though the contact fails CFR.
  EXPECT_TRUE(q.success);
  EXPECT_FALSE(q.collision_free);
  EpisodeBuilder transient(5.0);
  transient.predicate("success", 0.0, 5.0);
  transient.contact(2.0, 2.0, human_contact("right_hand", human::BodyRegion::kHand, 300.0));
  const EpisodeMetrics t = compute_metrics(ScenarioContract{}, transient.log());
  EXPECT_TRUE(t.critical_contact);
  EXPECT_FALSE(t.success);
  EXPECT_EQ(*t.primary_label, FailureLabel::kCriticalContact);
  // The transient factor is configurable: at 1.05 (147 N on the hand) 150 N is critical.
  MetricConstants tight;
  tight.transient_factor = 1.05;
  EXPECT_TRUE(compute_metrics(ScenarioContract{}, quasi.log(), tight).critical_contact);
  // Below the limit: HCS untouched.
  EpisodeBuilder light(5.0);
  light.contact(2.0, 2.0, human_contact("right_hand", human::BodyRegion::kHand, 100.0));
  EXPECT_DOUBLE_EQ(compute_metrics(ScenarioContract{}, light.log()).hcs, 1.0);
}

// Script safety conditions (safety.no_contact, safety.max_violation) make success depend on
// any human contact outside the permitted pairs and on the separation violation time.
TEST(SafetyConditions, NoContactFailsSuccessOnAnyUnpermittedContact) {
  EpisodeBuilder b(5.0);
  b.predicate("success", 0.0, 5.0);
  b.contact(2.0, 2.0, human_contact("right_hand", human::BodyRegion::kHand, 5.0));
  ScenarioContract strict;
  strict.success_requires_no_contact = true;
  const EpisodeMetrics m = compute_metrics(strict, b.log());
  EXPECT_FALSE(m.success);
  EXPECT_EQ(*m.primary_label, FailureLabel::kContact);
  // Without the condition the same light contact fails CFR only.
  EXPECT_TRUE(compute_metrics(ScenarioContract{}, b.log()).success);
  // A permitted contact does not count.
  ScenarioContract permitted = handover_contract();
  permitted.success_requires_no_contact = true;
  EpisodeBuilder handover(6.0);
  handover.predicate("success", 0.0, 6.0).event(1.0, "offer.hold_stable").event(4.0, "release.end");
  handover.contact(2.0, 3.0, human_contact("right_hand", human::BodyRegion::kHand, 10.0));
  EXPECT_TRUE(compute_metrics(permitted, handover.log()).success);
}

TEST(SafetyConditions, ViolationTimeBeyondTheBoundFailsSuccess) {
  // 1 s of violation (d = 0.3 m < S_p while approaching at 0.5 m/s), HCS 0.5 over 2 s.
  EpisodeBuilder b(5.0);
  b.predicate("success", 0.0, 5.0).separation(1.05, 3.0, 0.8).separation(2.05, 3.0, 0.3, 0.5, 0.5);
  ScenarioContract bounded;
  bounded.success_max_violation = 0.9;
  const EpisodeMetrics m = compute_metrics(bounded, b.log());
  EXPECT_NEAR(m.violation_time, 1.0, 1e-9);
  EXPECT_FALSE(m.success);
  EXPECT_EQ(*m.primary_label, FailureLabel::kUnsafeProximity);
  bounded.success_max_violation = 1.1;
  EXPECT_TRUE(compute_metrics(bounded, b.log()).success);
  // A violation as long as the bound is within it, whichever way the control periods' sum
  // rounds (1.5 + 2e-13 s at 2.5 ms physics steps); a microsecond more is not.
  bounded.success_max_violation = m.violation_time - 2e-13;
  EXPECT_TRUE(compute_metrics(bounded, b.log()).success);
  bounded.success_max_violation = m.violation_time - 1e-6;
  EXPECT_FALSE(compute_metrics(bounded, b.log()).success);
  // A short violation under the bound with a high HCS: success; over a zero bound: not, and
  // labelled unsafe_proximity though HCS is above its label threshold.
  EpisodeBuilder brief(5.0);
  brief.predicate("success", 0.0, 5.0).separation(0.05, 5.0, 0.8).separation(2.05, 2.1, 0.3, 0.5, 0.5);
  bounded.success_max_violation = 0.0;
  const EpisodeMetrics z = compute_metrics(bounded, brief.log());
  EXPECT_GT(z.hcs, 0.9);
  EXPECT_FALSE(z.success);
  EXPECT_EQ(*z.primary_label, FailureLabel::kUnsafeProximity);
  EXPECT_TRUE(compute_metrics(ScenarioContract{}, brief.log()).success);
}

TEST(IdleRatio, AllowedTimeMinusWaits) {
  ScenarioContract contract;
  contract.allowed_from = "go.stroke";
  contract.robot_waits.push_back({"stop.stroke", "go2.stroke"});
  // Allowed: [1, 10] minus [4, 6] = 7 s; the robot moves in [1, 4] and [6, 8]: still 2 s.
  EpisodeBuilder b(10.0);
  b.event(1.0, "go.stroke").event(4.0, "stop.stroke").event(6.0, "go2.stroke");
  b.move_x(1.0, 4.0, 0.05).move_x(6.0, 8.0, 0.05).predicate("success", 9.0, 10.0);
  const EpisodeMetrics m = compute_metrics(contract, b.log());
  EXPECT_NEAR(*m.idle_ratio, 2.0 / 7.0, 1e-9);
  // Never allowed (no go): not applicable.
  EpisodeBuilder never(10.0);
  never.predicate("success", 9.0, 10.0);
  EXPECT_FALSE(compute_metrics(contract, never.log()).idle_ratio.has_value());
  // An SSM-required stop (human at 0.2 m) is not counted as idle time.
  b.separation(8.05, 10.0, 0.2);
  EXPECT_NEAR(*compute_metrics(contract, b.log()).idle_ratio, 0.0, 1e-9);
}

// IR and the fluency metrics describe how a task was done: a failed episode has none. A robot
// that never rests (random actions) would otherwise have the best IR and R-IDLE of all.
TEST(IdleRatio, NotApplicableToAFailedEpisode) {
  ScenarioContract contract;
  contract.allowed_from = "go.stroke";
  contract.human_waits.push_back({"offer.hold_stable", "release.start"});
  EpisodeBuilder restless(10.0);
  restless.event(1.0, "go.stroke").event(2.0, "offer.hold_stable").move_x(0.0, 10.0, 0.05);
  const EpisodeMetrics m = compute_metrics(contract, restless.log());
  EXPECT_FALSE(m.success);
  EXPECT_FALSE(m.idle_ratio.has_value());
  EXPECT_FALSE(m.r_idle.has_value());
  EXPECT_FALSE(m.h_idle.has_value());
  EXPECT_FALSE(m.c_act.has_value());
  EXPECT_FALSE(m.f_del.has_value());
  restless.predicate("success", 9.0, 10.0);
  const EpisodeMetrics n = compute_metrics(contract, restless.log());
  EXPECT_NEAR(*n.idle_ratio, 0.0, 1e-9);
  EXPECT_NEAR(*n.r_idle, 0.0, 1e-9);
  EXPECT_NEAR(*n.h_idle, 0.8, 1e-9);
}

TEST(Cir, LatestIntentAndNeverTheContradictedOutcome) {
  ScenarioContract contract;
  contract.contradiction = true;
  EpisodeBuilder good(5.0, {"success", "intent", "contradicted"});
  good.predicate("intent", 4.0, 5.0).predicate("success", 4.0, 5.0);
  EXPECT_DOUBLE_EQ(*compute_metrics(contract, good.log()).cir, 1.0);
  EpisodeBuilder blind(5.0, {"success", "intent", "contradicted"});
  blind.predicate("intent", 4.0, 5.0).predicate("contradicted", 2.0, 2.5);
  const EpisodeMetrics m = compute_metrics(contract, blind.log());
  EXPECT_DOUBLE_EQ(*m.cir, 0.0);
  EXPECT_EQ(*m.primary_label, FailureLabel::kIgnoredContradiction);
  EXPECT_FALSE(compute_metrics(ScenarioContract{}, good.log()).cir.has_value());
  // With a contradiction event: applicable only once it happened.
  contract.contradiction_event = "wave_off.start";
  EXPECT_FALSE(compute_metrics(contract, good.log()).cir.has_value());
  good.event(1.0, "wave_off.start", EventKind::kActStart);
  EXPECT_DOUBLE_EQ(*compute_metrics(contract, good.log()).cir, 1.0);
}

TEST(Dsr, SuccessAfterTheDisruption) {
  ScenarioContract contract;
  contract.disruption_event = "reach.start";
  EpisodeBuilder b(5.0);
  b.event(1.0, "reach.start").predicate("success", 3.0, 5.0);
  EXPECT_DOUBLE_EQ(*compute_metrics(contract, b.log()).dsr, 1.0);
  EpisodeBuilder failed(5.0);
  failed.event(1.0, "reach.start");
  const EpisodeMetrics m = compute_metrics(contract, failed.log());
  EXPECT_DOUBLE_EQ(*m.dsr, 0.0);
  EXPECT_NE(std::count(m.labels.begin(), m.labels.end(), FailureLabel::kNoRecovery), 0);
  // No disruption happened: not applicable.
  EXPECT_FALSE(compute_metrics(contract, EpisodeBuilder(5.0).log()).dsr.has_value());
}

TEST(Fluency, IdleConcurrencyAndDelay) {
  ScenarioContract contract;
  contract.robot_acts.push_back({"take", std::nullopt});
  contract.human_waits.push_back({"offer.hold_stable", "release.start"});
  // Human offers in [0, 2] (waits from 1.0 to 3.0), robot moves in [3, 5]; horizon 10.
  EpisodeBuilder b(10.0);
  b.event(0.0, "offer.start", EventKind::kActStart).event(2.0, "offer.end", EventKind::kActEnd);
  b.event(1.0, "offer.hold_stable").event(3.0, "release.start", EventKind::kActStart);
  b.event(4.0, "release.end", EventKind::kActEnd);
  b.move_x(3.0, 5.0, 0.05).event(5.0, "take.end", EventKind::kActEnd, Actor::kRobot);
  b.predicate("success", 9.0, 10.0);
  const EpisodeMetrics m = compute_metrics(contract, b.log());
  EXPECT_NEAR(*m.r_idle, 8.0 / 10.0, 1e-9);
  EXPECT_NEAR(*m.h_idle, 2.0 / 10.0, 1e-9);
  EXPECT_NEAR(*m.c_act, 1.0 / 10.0, 1e-9);  // robot moving while "release" runs: [3, 4]
  // Hand-offs: offer ends 2.0 -> take starts 3.0 (1 s); take ends 5.0 -> no later human act.
  // release ends 4.0 while the robot acts: not a hand-off.
  EXPECT_NEAR(*m.f_del, 1.0, 1e-9);
}

TEST(Labels, PrimaryIsTheFirstInPriorityOrder) {
  // Contact and no response and timeout: primary = contact; all listed in order.
  EpisodeBuilder b(5.0);
  b.move_x(0.0, 5.0, 0.1).event(1.0, "stop.stroke");
  b.contact(2.0, 2.0, human_contact("left_forearm", human::BodyRegion::kForearm, 20.0));
  const EpisodeMetrics m = compute_metrics(stop_contract(1.0), b.log());
  EXPECT_EQ(*m.primary_label, FailureLabel::kContact);
  EXPECT_EQ(m.labels, (std::vector<FailureLabel>{FailureLabel::kContact, FailureLabel::kNoResponse,
                                                 FailureLabel::kTimeout}));
  EXPECT_EQ(to_string(FailureLabel::kIgnoredContradiction), "ignored_contradiction");
}

TEST(Labels, SeriesDrivenLabels) {
  EpisodeBuilder b(5.0, {"success", "dropped", "grasp_failed", "wrong_target"});
  b.predicate("dropped", 2.0, 2.0).predicate("grasp_failed", 1.0, 1.0);
  const EpisodeMetrics m = compute_metrics(ScenarioContract{}, b.log());
  EXPECT_EQ(m.labels, (std::vector<FailureLabel>{FailureLabel::kDrop, FailureLabel::kManipulation,
                                                 FailureLabel::kTimeout}));
  EXPECT_EQ(*m.primary_label, FailureLabel::kDrop);
}

}  // namespace
}  // namespace hribench::eval
