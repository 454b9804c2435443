// No worse robot beats the oracle (issue 16; docs/metrics.md, "No metric rewards doing less").
// Every task is run with the oracle and with the four policies below it on the ladder: noop
// (never moves), random (uniform random actions), blind (the plan at once, ignoring every cue
// and `after`) and reactive (waits for the cues, no safety layer, no re-planning). None of
// them may score better than the oracle on a metric the oracle's behaviour is meant to win;
// the exceptions are listed below with the reason docs/metrics.md gives for each.
// One seeded episode per task (seeds the oracle solves, as in oracle_tasks_test.cc).
// HRIB_LADDER_PRINT=1 prints every comparison.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "eval/metrics.h"
#include "eval/task_run.h"

namespace hribench::eval {
namespace {

using testing::run_task;

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

class Ladder : public ::testing::TestWithParam<TaskCase> {};

TEST_P(Ladder, NoWorseRobotBeatsTheOracle) {
  const ScoredEpisode oracle = run_task(GetParam().file, GetParam().seed, "oracle");
  ASSERT_TRUE(oracle.metrics.success) << "the oracle must solve the episode the ladder compares on";
  const std::string& task = oracle.log.task;
  for (const char* policy : {"noop", "random", "blind", "reactive"}) {
    const ScoredEpisode worse = run_task(GetParam().file, GetParam().seed, policy);
    for (const Metric& metric : metrics()) {
      const std::optional<double> o = metric.value(oracle.metrics);
      const std::optional<double> w = metric.value(worse.metrics);
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
}

INSTANTIATE_TEST_SUITE_P(Tasks, Ladder,
                         ::testing::Values(TaskCase{"tasks/I1_point_pick.yaml", 0},
                                           TaskCase{"tasks/I2_gesture_delivery.yaml", 0},
                                           TaskCase{"tasks/I3_demo_imitate.yaml", 0},
                                           TaskCase{"tasks/I4_stop_go.yaml", 1},
                                           TaskCase{"tasks/I5_contradiction.yaml", 0},
                                           TaskCase{"tasks/I5_contradiction.yaml", 1},
                                           TaskCase{"tasks/C1_handover_h2r.yaml", 0},
                                           TaskCase{"tasks/C2_handover_r2h.yaml", 1},
                                           TaskCase{"tasks/C3_box_retrieval.yaml", 0},
                                           TaskCase{"tasks/C4_co_lift.yaml", 0},
                                           TaskCase{"tasks/X1_intrusion_yield.yaml", 0},
                                           TaskCase{"tasks/X2_object_moved.yaml", 0},
                                           TaskCase{"tasks/X3_someone_else_places.yaml", 0},
                                           TaskCase{"tasks/X4_blocked_target.yaml", 0}));

}  // namespace
}  // namespace hribench::eval
