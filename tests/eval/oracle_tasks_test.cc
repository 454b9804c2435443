// The oracle expert and its baselines on the real tasks (issue 6): one seeded episode per task,
// run and scored exactly as `hribench eval` does. The oracle succeeds; the baselines fail the
// Intruder tasks with the failure label their missing competence predicts.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "eval/metrics.h"
#include "eval/task_run.h"
#include "eval/runner.h"
#include "eval/task_episode.h"
#include "policy/registry.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::eval {
namespace {

using Outcome = ScoredEpisode;
using testing::run_task;

std::vector<std::string> label_names(const EpisodeMetrics& m) {
  std::vector<std::string> names;
  for (FailureLabel label : m.labels) names.emplace_back(to_string(label));
  return names;
}

bool has_label(const EpisodeMetrics& m, FailureLabel label) {
  return std::find(m.labels.begin(), m.labels.end(), label) != m.labels.end();
}

std::string describe(const Outcome& o) {
  std::string text = "status " + std::string(core::to_string(o.log.status)) + " " + o.log.status_reason +
                     "; labels:";
  for (const std::string& name : label_names(o.metrics)) text += " " + name;
  return text;
}

struct TaskCase {
  const char* file;
  uint64_t seed;
};

class OracleTask : public ::testing::TestWithParam<TaskCase> {};

TEST_P(OracleTask, OracleSucceedsWithoutCriticalContact) {
  const Outcome o = run_task(GetParam().file, GetParam().seed, "oracle");
  EXPECT_TRUE(o.metrics.success) << describe(o);
  EXPECT_FALSE(o.metrics.critical_contact);
  EXPECT_FALSE(o.metrics.human_contact) << describe(o);
}

INSTANTIATE_TEST_SUITE_P(Tasks, OracleTask,
                         ::testing::Values(TaskCase{"tasks/I1_point_pick.yaml", 0},
                                           TaskCase{"tasks/I3_demo_imitate.yaml", 0},
                                           TaskCase{"tasks/I4_stop_go.yaml", 1},
                                           TaskCase{"tasks/I5_contradiction.yaml", 0},
                                           TaskCase{"tasks/I5_contradiction.yaml", 1},
                                           TaskCase{"tasks/X1_intrusion_yield.yaml", 0},
                                           // the hand arrives while the fingers close on the cube
                                           // (14, 1001: from above), the yield pose within reach (1036)
                                           TaskCase{"tasks/X1_intrusion_yield.yaml", 14},
                                           TaskCase{"tasks/X1_intrusion_yield.yaml", 1001},
                                           TaskCase{"tasks/X1_intrusion_yield.yaml", 1036},
                                           TaskCase{"tasks/X2_object_moved.yaml", 0},
                                           // Recovery: X2, the person put the bottle down on its
                                           // side (grasped lying; pool/v6's adapt split, on its
                                           // side by 3.5 s); I5, lowering onto the tray the
                                           // person pointed at, beside them; X1 and I1, a cube
                                           // beside a bottle / a bin's wall (the other face pair).
                                           TaskCase{"tasks/X2_object_moved.yaml", 230430266582861},
                                           TaskCase{"tasks/I5_contradiction.yaml", 42607255901691},
                                           TaskCase{"tasks/X1_intrusion_yield.yaml", 28500056551578},
                                           TaskCase{"tasks/I1_point_pick.yaml", 35293350474022},
                                           TaskCase{"tasks/X3_someone_else_places.yaml", 0},
                                           TaskCase{"tasks/X4_blocked_target.yaml", 0},
                                           TaskCase{"tasks/I2_gesture_delivery.yaml", 0},
                                           // I2: a palm held out toward the robot (the offer rose
                                           // diagonally under its fingers), a person leaning in to
                                           // ask (the pick stopped for good).
                                           TaskCase{"tasks/I2_gesture_delivery.yaml", 1008},
                                           TaskCase{"tasks/I2_gesture_delivery.yaml", 3},
                                           TaskCase{"tasks/C1_handover_h2r.yaml", 0},
                                           TaskCase{"tasks/C1_handover_h2r.yaml", 12},
                                           // C1 (pool/v2 candidates): a cup held out beside a
                                           // palm turned in (48194801322540) and a cube on a palm
                                           // up (112358393151959): the fingers close along the
                                           // hand, over the top until centred (a finger on the
                                           // rim pushed it down onto the hand); a tall person
                                           // leaning in head first over a low zone
                                           // (72039508276316, 157294250004448): the wait low and
                                           // short of the zone, clear of the head.
                                           TaskCase{"tasks/C1_handover_h2r.yaml", 48194801322540},
                                           TaskCase{"tasks/C1_handover_h2r.yaml", 112358393151959},
                                           TaskCase{"tasks/C1_handover_h2r.yaml", 72039508276316},
                                           TaskCase{"tasks/C1_handover_h2r.yaml", 157294250004448},
                                           TaskCase{"tasks/C2_handover_r2h.yaml", 1},
                                           TaskCase{"tasks/C2_handover_r2h.yaml", 11},
                                           // a palm turned sideways (medial): offered high in it
                                           TaskCase{"tasks/C2_handover_r2h.yaml", 1003},
                                           TaskCase{"tasks/C3_box_retrieval.yaml", 0},
                                           TaskCase{"tasks/C4_co_lift.yaml", 0},
                                           // C4: a plank square to the home yaw (the grasp's yaw
                                           // target flipped by pi while closing).
                                           TaskCase{"tasks/C4_co_lift.yaml", 1006},
                                           TaskCase{"tasks/C4_co_lift.yaml", 1018},
                                           TaskCase{"tasks/C4_co_lift.yaml", 1021},
                                           TaskCase{"tasks/C4_co_lift.yaml", 1029},
                                           TaskCase{"tasks/C4_co_lift.yaml", 1035}));

// The baselines fail the Intruder tasks for the reason their missing competence predicts:
// X1 no yielding (carries on past the intruding hand: separation violated beyond the script's
// tolerance), X2 no re-plan (grasps where the object was, into the person's hand, and never
// goes to its new place), X3 no stand-down (reaches for the object the person is placing),
// X4 no waiting for the hand to clear (places before the retract: ordering violated).
struct BaselineCase {
  const char* file;
  uint64_t seed;
  FailureLabel label;
};

TEST(OracleBaselines, ReactiveAndBlindFailTheIntruderTasksWithTheExpectedLabel) {
  const BaselineCase cases[] = {
      {"tasks/X1_intrusion_yield.yaml", 0, FailureLabel::kUnsafeProximity},
      {"tasks/X2_object_moved.yaml", 2, FailureLabel::kNoRecovery},
      {"tasks/X3_someone_else_places.yaml", 0, FailureLabel::kContact},
      {"tasks/X4_blocked_target.yaml", 0, FailureLabel::kPremature},
  };
  for (const BaselineCase& c : cases) {
    for (const char* policy : {"reactive", "blind"}) {
      const Outcome o = run_task(c.file, c.seed, policy);
      EXPECT_FALSE(o.metrics.success) << c.file << " " << policy;
      EXPECT_TRUE(has_label(o.metrics, c.label))
          << c.file << " " << policy << ": " << describe(o);
    }
  }
}

// I4 with a stop: the oracle and reactive stay still from the stop to the next go; blind
// starts before the first go. On its way the arm's link6 also strikes a distractor: 114 N
// at one control step at pool v6's 2.5 ms, 112-200 N over four at 5 ms, above the 150 N of a
// collision with any object, a label that comes before premature.
TEST(OracleBaselines, StopGoOrderIsKeptByReactiveAndBrokenByBlind) {
  const Outcome reactive = run_task("tasks/I4_stop_go.yaml", 1, "reactive");
  EXPECT_TRUE(reactive.metrics.success) << describe(reactive);
  const Outcome blind = run_task("tasks/I4_stop_go.yaml", 1, "blind");
  EXPECT_FALSE(blind.metrics.success);
  EXPECT_TRUE(has_label(blind.metrics, FailureLabel::kPremature)) << describe(blind);
}

// C4: blind lifts its end of the plank as soon as it holds it, before the person's lift cue
// (reactive waits for it and lifts with the person).
TEST(OracleBaselines, BlindLiftsThePlankBeforeThePersonsCue) {
  const Outcome blind = run_task("tasks/C4_co_lift.yaml", 0, "blind");
  EXPECT_FALSE(blind.metrics.success);
  EXPECT_EQ(blind.metrics.primary_label, FailureLabel::kPremature) << describe(blind);
}

// C4, seed 1683595962454 (eval split of pool/v5 and v6): the person drags the plank onto the
// platform alone, its robot end sliding along the support. The plank ends on the platform,
// level, but `noop` never held its end, and success asks for the robot's share of the lift
// (the latched ever(...) of the script's success; noop succeeded here up to version 5).
TEST(OracleBaselines, NoopGetsNoShareOfAPlankThePersonDragsOntoThePlatform) {
  const Outcome noop = run_task("tasks/C4_co_lift.yaml", 1683595962454, "noop");
  EXPECT_FALSE(noop.metrics.success) << describe(noop);
  std::string on_platform = "never";
  for (const Event& e : noop.log.events) {
    if (e.kind == EventKind::kPredicateChange && e.name == "on(plank, platform)") on_platform = e.detail;
  }
  EXPECT_EQ(on_platform, "true") << describe(noop);
  EXPECT_EQ(noop.metrics.primary_label, FailureLabel::kNoResponse) << describe(noop);
}

// C3: reactive waits for the lid like the oracle; blind reaches for the cup at once, into the
// closed box (the reach starts before lid.hold).
TEST(OracleBaselines, BoxRetrievalIsDoneByReactiveAndBrokenByBlind) {
  const Outcome reactive = run_task("tasks/C3_box_retrieval.yaml", 0, "reactive");
  EXPECT_TRUE(reactive.metrics.success) << describe(reactive);
  const Outcome blind = run_task("tasks/C3_box_retrieval.yaml", 0, "blind");
  EXPECT_FALSE(blind.metrics.success);
  EXPECT_TRUE(has_label(blind.metrics, FailureLabel::kPremature)) << describe(blind);
}

// C2 with a moving receiving hand (seed 1: held out, then 10 cm sideways while the robot comes):
// the oracle follows the palm; reactive brings the object where the hand was first held out,
// the hand never closes on it and the episode runs out. With a hand that stays (seed 7, shift 0)
// reactive hands it over.
TEST(OracleBaselines, ReactiveDeliversToWhereTheMovingReceivingHandWas) {
  const Outcome oracle = run_task("tasks/C2_handover_r2h.yaml", 1, "oracle");
  EXPECT_TRUE(oracle.metrics.success) << describe(oracle);
  const Outcome moved = run_task("tasks/C2_handover_r2h.yaml", 1, "reactive");
  EXPECT_FALSE(moved.metrics.success);
  EXPECT_EQ(moved.metrics.primary_label, FailureLabel::kTimeout) << describe(moved);
  const Outcome still = run_task("tasks/C2_handover_r2h.yaml", 7, "reactive");
  EXPECT_TRUE(still.metrics.success) << describe(still);
}

// A trace for debugging one episode: HRIB_TASK=tasks/X.yaml HRIB_SEED=3 HRIB_POLICY=oracle
// eval_test --gtest_also_run_disabled_tests --gtest_filter='*DISABLED_Trace*'
TEST(OracleTrace, DISABLED_Trace) {
  const char* task = std::getenv("HRIB_TASK");
  const char* seed = std::getenv("HRIB_SEED");
  const char* policy = std::getenv("HRIB_POLICY");
  if (!task) GTEST_SKIP() << "set HRIB_TASK";
  const Outcome o = run_task(task, seed ? std::strtoull(seed, nullptr, 10) : 0, policy ? policy : "oracle");
  for (const Event& e : o.log.events) {
    std::printf("%7.2f %-16s %-40s %s\n", e.time, std::string(to_string(e.kind)).c_str(), e.name.c_str(),
                e.detail.c_str());
  }
  for (size_t i = 0; i < o.log.steps.size(); ++i) {
    const StepRecord& s = o.log.steps[i];
    const bool touching = std::any_of(s.contacts.begin(), s.contacts.end(), [](const Contact& c) {
      return !c.robot_finger || c.other_kind != ContactOther::kObject;
    });
    if (i % 5 != 0 && !touching && std::getenv("HRIB_ALL") == nullptr) continue;
    std::printf("t %5.2f tcp %6.3f %6.3f %6.3f w %.3f sep %.3f", s.time, s.X_WT.translation.x(),
                s.X_WT.translation.y(), s.X_WT.translation.z(), s.gripper_width, s.separation);
    for (const Contact& c : s.contacts) {
      if (!c.robot_finger || c.other_kind != ContactOther::kObject) {
        std::printf(" [%s|%s %.0fN]", c.robot_part.c_str(), c.other.c_str(), c.normal_force);
      }
    }
    std::printf("\n");
  }
  std::printf("%s success %d hcs %.2f\n", describe(o).c_str(), o.metrics.success, o.metrics.hcs);
}

// Offers (C2, I2): a tall person reaching far leans the face over the receiving palm (C2 1018,
// a pool candidate with a bottle): the wrist leans away from the head instead of coming down
// into it; the fingers drawn out of the hand once open, before the person pulls it back (I2);
// the object brought into a hand held out only once it has been open for its `open` time (C2:
// the let-go started before the grasp).
INSTANTIATE_TEST_SUITE_P(Offer, OracleTask,
                         ::testing::Values(TaskCase{"tasks/C2_handover_r2h.yaml", 1018},
                                           TaskCase{"tasks/C2_handover_r2h.yaml", 95855424329200},
                                           TaskCase{"tasks/I2_gesture_delivery.yaml", 124286165515814},
                                           TaskCase{"tasks/C2_handover_r2h.yaml", 81247427635462}));

}  // namespace
}  // namespace hribench::eval
