// No worse robot beats the oracle (issue 16; docs/metrics.md, "No metric rewards doing less").
// Every task is run with the oracle and with the four policies below it on the ladder: noop
// (never moves), random (uniform random actions), blind (the plan at once, ignoring every cue
// and `after`) and reactive (waits for the cues, no safety layer, no re-planning). None of
// them may score better than the oracle on a metric the oracle's behaviour is meant to win;
// the exceptions are listed below with the reason docs/metrics.md gives for each.
// One seeded episode per task (seeds the oracle solves, as in oracle_tasks_test.cc).
// The dense reward's return (eval/reward.h) must order oracle, reactive and blind too, on
// seeds 0-4 of every task: the metrics' ladder seed here, the other seeds the oracle solves in
// DenseLadder.
// HRIB_LADDER_PRINT=1 prints every comparison.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "eval/metrics.h"
#include "eval/reward.h"
#include "eval/task_run.h"

namespace hribench::eval {
namespace {

using testing::RewardedEpisode;
using testing::run_task_rewarded;

struct Metric {
  const char* name;
  bool higher_is_better;
  std::function<std::optional<double>(const EpisodeMetrics&)> value;
  double resolution = 0;  // a margin up to this is no win: one control step, 1 % of a fraction
};

constexpr double kStep = 0.05;    // s, one control step
constexpr double kShare = 0.01;   // of a fraction in [0, 1]

const std::vector<Metric>& metrics() {
  static const std::vector<Metric> all = {
      {"CSR", true, [](const EpisodeMetrics& m) { return std::optional<double>(m.success ? 1 : 0); }},
      {"CT", false, [](const EpisodeMetrics& m) { return std::optional<double>(m.completion_time); }, kStep},
      {"Rsp", false, [](const EpisodeMetrics& m) { return m.response_latency; }, kStep},
      {"TSync", true, [](const EpisodeMetrics& m) { return m.tsync; }, kShare},
      {"OC", true, [](const EpisodeMetrics& m) { return m.order_compliance; }, kShare},
      {"IR", false, [](const EpisodeMetrics& m) { return m.idle_ratio; }, kShare},
      {"CFR", true, [](const EpisodeMetrics& m) { return std::optional<double>(m.collision_free ? 1 : 0); }},
      {"HCS", true, [](const EpisodeMetrics& m) { return std::optional<double>(m.hcs); }, kShare},
      {"CIR", true, [](const EpisodeMetrics& m) { return m.cir; }},
      {"DSR", true, [](const EpisodeMetrics& m) { return m.dsr; }},
      {"R-IDLE", false, [](const EpisodeMetrics& m) { return m.r_idle; }, kShare},
      {"H-IDLE", false, [](const EpisodeMetrics& m) { return m.h_idle; }, kShare},
      {"C-ACT", true, [](const EpisodeMetrics& m) { return m.c_act; }, kShare},
      {"F-DEL", false, [](const EpisodeMetrics& m) { return m.f_del; }, kStep},
  };
  return all;
}

// A documented exception: `policy` may beat the oracle on `metric` (in every task, or in the
// tasks listed), for the reason docs/metrics.md gives.
struct Exception {
  const char* metric;
  const char* policy;
  std::vector<std::string> tasks;  // empty: every task
  const char* reason;
};

// The reasons, as docs/metrics.md ("No metric rewards doing less") gives them.
constexpr const char* kNoSafetyLayer =
    "reactive has the oracle's skill and waits for the same cues, without the safety layer: it "
    "never pauses, slows or backs off for the person, so where it succeeds it can finish sooner, "
    "idle less, act more at once with the person, start sooner after a cue and meet a sync "
    "target more closely; HCS and CFR show the cost";
constexpr const char* kBlindAsReactive =
    "blind is reactive that does not wait for after events; where every event it should wait "
    "for comes before it is ready (the person asks while it still picks the object up), it does "
    "what reactive does";
constexpr const char* kAtRest =
    "a robot at rest at its home pose, or jittering about it, stays far from the person: Safety "
    "is read beside CSR";
constexpr const char* kNotWhereAsked =
    "HCS scores how close the robot came to the person over whatever it did: a robot that does "
    "not go where the person asks (I5's redirect to a tray beside them, C2's receiving hand that "
    "moves on) stays farther away; CSR, CIR and the labels show the failure";
constexpr const char* kAlreadyStill =
    "a robot at rest already does what a stop or intrusion cue asks (latency 0)";

const std::vector<Exception>& exceptions() {
  static const std::vector<Exception> all = [] {
    std::vector<Exception> list;
    for (const char* metric : {"CT", "Rsp", "TSync", "IR", "R-IDLE", "H-IDLE", "C-ACT", "F-DEL"}) {
      list.push_back({metric, "reactive", {}, kNoSafetyLayer});
      list.push_back({metric, "blind", {}, kBlindAsReactive});
    }
    list.push_back({"HCS", "reactive", {"contradiction", "handover_r2h"}, kNotWhereAsked});
    list.push_back({"HCS", "blind", {"contradiction", "handover_r2h"}, kNotWhereAsked});
    for (const char* policy : {"noop", "random"}) {
      list.push_back({"HCS", policy, {}, kAtRest});
      list.push_back({"CFR", policy, {}, kAtRest});
    }
    list.push_back({"Rsp", "noop", {}, kAlreadyStill});
    return list;
  }();
  return all;
}

const Exception* exception_for(const std::string& metric, const std::string& policy,
                               const std::string& task) {
  for (const Exception& e : exceptions()) {
    if (metric != e.metric || policy != e.policy) continue;
    if (e.tasks.empty() || std::find(e.tasks.begin(), e.tasks.end(), task) != e.tasks.end()) return &e;
  }
  return nullptr;
}

struct TaskCase {
  const char* file;
  uint64_t seed;
};
void PrintTo(const TaskCase& c, std::ostream* os) { *os << c.file << " seed " << c.seed; }

// The metrics' ladder compares on these seeds (the oracle solves them).
const std::vector<TaskCase> kLadderCases = {
    {"tasks/I1_point_pick.yaml", 0},     {"tasks/I2_gesture_delivery.yaml", 0},
    {"tasks/I3_demo_imitate.yaml", 0},   {"tasks/I4_stop_go.yaml", 1},
    {"tasks/I5_contradiction.yaml", 0},  {"tasks/I5_contradiction.yaml", 1},
    {"tasks/C1_handover_h2r.yaml", 0},   {"tasks/C2_handover_r2h.yaml", 1},
    {"tasks/C3_box_retrieval.yaml", 0},  {"tasks/C4_co_lift.yaml", 0},
    {"tasks/X1_intrusion_yield.yaml", 0}, {"tasks/X2_object_moved.yaml", 0},
    {"tasks/X3_someone_else_places.yaml", 0}, {"tasks/X4_blocked_target.yaml", 0}};

// Seeds 0-4 that the oracle does not solve, left out of DenseLadder: C1 seed 4 since pool v8
// (its grasp of the offered bottle closes one control step later than with pool v7's person,
// and the bottle, let go over the bin, falls 7 cm: faster than `dropped`'s 1 m/s; the pool's
// executable filter rejects such candidates).
const std::vector<TaskCase> kOracleFails = {{"tasks/C1_handover_h2r.yaml", 4}};

// Seeds 0-4 of every task that the metrics' ladder does not already run and the oracle solves.
std::vector<TaskCase> other_seeds_0_to_4() {
  std::vector<TaskCase> cases;
  for (size_t i = 0; i < kLadderCases.size(); ++i) {
    const std::string file = kLadderCases[i].file;
    if (i > 0 && file == kLadderCases[i - 1].file) continue;
    for (uint64_t seed = 0; seed < 5; ++seed) {
      const auto listed = [&](const std::vector<TaskCase>& list) {
        return std::any_of(list.begin(), list.end(), [&](const TaskCase& c) { return c.file == file && c.seed == seed; });
      };
      if (!listed(kLadderCases) && !listed(kOracleFails)) cases.push_back({kLadderCases[i].file, seed});
    }
  }
  return cases;
}

// Between two episodes that end alike (both succeed or both fail) the dense return's shaping
// terms may put the lower rung ahead by at most this much (3 % of the success bonus): the
// oracle's safety layer can keep it near the person a few control steps longer than reactive
// (docs/python.md "Rewards" lists the cases).
constexpr double kShapingSlack = 0.3;

// The dense return orders `better` above `worse` (docs/python.md "Rewards"): the better rung
// does not fail where the worse one succeeds; where it succeeds and the worse one fails, its
// return is higher; otherwise its return is at least the worse one's less kShapingSlack.
void expect_dense_order(const RewardedEpisode& better, const char* better_name, const RewardedEpisode& worse,
                        const char* worse_name, const TaskCase& c) {
  const double b = better.dense_return.total();
  const double w = worse.dense_return.total();
  const bool b_success = better.scored.metrics.success;
  const bool w_success = worse.scored.metrics.success;
  if (std::getenv("HRIB_LADDER_PRINT")) {
    std::printf("%s seed %llu dense return: %s %.4f (%s), %s %.4f (%s)\n", c.file,
                static_cast<unsigned long long>(c.seed), better_name, b, b_success ? "success" : "failure",
                worse_name, w, w_success ? "success" : "failure");
  }
  const std::string where = std::string(c.file) + " seed " + std::to_string(c.seed) + ": " + better_name + " " +
                            std::to_string(b) + ", " + worse_name + " " + std::to_string(w);
  EXPECT_FALSE(w_success && !b_success) << worse_name << " succeeds where " << better_name << " fails in " << where;
  if (b_success && !w_success) {
    EXPECT_GT(b, w) << where;
  } else {
    EXPECT_GE(b, w - kShapingSlack) << where;
  }
}

void expect_dense_ladder(const RewardedEpisode& oracle, const RewardedEpisode& reactive,
                         const RewardedEpisode& blind, const TaskCase& c) {
  expect_dense_order(oracle, "oracle", reactive, "reactive", c);
  expect_dense_order(reactive, "reactive", blind, "blind", c);
}

class Ladder : public ::testing::TestWithParam<TaskCase> {};

TEST_P(Ladder, NoWorseRobotBeatsTheOracle) {
  const RewardedEpisode oracle = run_task_rewarded(GetParam().file, GetParam().seed, "oracle");
  ASSERT_TRUE(oracle.scored.metrics.success) << "the oracle must solve the episode the ladder compares on";
  const std::string& task = oracle.scored.log.task;
  std::vector<RewardedEpisode> below;
  for (const char* policy : {"noop", "random", "blind", "reactive"}) {
    below.push_back(run_task_rewarded(GetParam().file, GetParam().seed, policy));
    const EpisodeMetrics& worse = below.back().scored.metrics;
    for (const Metric& metric : metrics()) {
      const std::optional<double> o = metric.value(oracle.scored.metrics);
      const std::optional<double> w = metric.value(worse);
      if (std::getenv("HRIB_LADDER_PRINT")) {
        std::printf("%s %s %s oracle %s %s\n", task.c_str(), policy, metric.name,
                    o ? std::to_string(*o).c_str() : "-", w ? std::to_string(*w).c_str() : "-");
      }
      if (!o || !w) continue;  // not applicable to one of them: nothing to compare
      const double margin = metric.higher_is_better ? *w - *o : *o - *w;
      if (margin <= metric.resolution + 1e-9) continue;
      const Exception* exception = exception_for(metric.name, policy, task);
      EXPECT_NE(exception, nullptr) << policy << " beats the oracle on " << metric.name << " in "
                                    << task << " seed " << GetParam().seed << ": " << *w
                                    << " against " << *o;
    }
  }
  expect_dense_ladder(oracle, below[3], below[2], GetParam());
}

INSTANTIATE_TEST_SUITE_P(Tasks, Ladder, ::testing::ValuesIn(kLadderCases));

class DenseLadder : public ::testing::TestWithParam<TaskCase> {};

TEST_P(DenseLadder, OracleAboveReactiveAboveBlind) {
  const RewardedEpisode oracle = run_task_rewarded(GetParam().file, GetParam().seed, "oracle");
  ASSERT_TRUE(oracle.scored.metrics.success) << "the oracle solves seeds 0-4 of every task";
  expect_dense_ladder(oracle, run_task_rewarded(GetParam().file, GetParam().seed, "reactive"),
                      run_task_rewarded(GetParam().file, GetParam().seed, "blind"), GetParam());
}

INSTANTIATE_TEST_SUITE_P(Tasks, DenseLadder, ::testing::ValuesIn(other_seeds_0_to_4()));

// What DenseLadder leaves out, it leaves out because the oracle fails it.
TEST(DenseLadderLeftOut, TheOracleFailsThem) {
  for (const TaskCase& c : kOracleFails) {
    EXPECT_FALSE(run_task_rewarded(c.file, c.seed, "oracle").scored.metrics.success) << c.file << " seed " << c.seed;
  }
}

}  // namespace
}  // namespace hribench::eval
