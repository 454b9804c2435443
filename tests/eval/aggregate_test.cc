#include "eval/aggregate.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hribench::eval {
namespace {

constexpr double kZ = 1.959963984540054;

TEST(Wilson, KnownValues) {
  // Published Wilson 95 % intervals (Newcombe 1998; Agresti & Coull 1998).
  const Estimate half = wilson_interval(5, 10, kZ);
  EXPECT_DOUBLE_EQ(half.value, 0.5);
  EXPECT_NEAR(half.low, 0.2366, 5e-5);
  EXPECT_NEAR(half.high, 0.7634, 5e-5);
  const Estimate none = wilson_interval(0, 10, kZ);
  EXPECT_DOUBLE_EQ(none.low, 0.0);
  EXPECT_NEAR(none.high, 0.2775, 5e-5);
  const Estimate all = wilson_interval(10, 10, kZ);
  EXPECT_NEAR(all.low, 0.7225, 5e-5);
  EXPECT_DOUBLE_EQ(all.high, 1.0);
  const Estimate eight = wilson_interval(8, 20, kZ);
  EXPECT_NEAR(eight.low, 0.2188, 5e-5);
  EXPECT_NEAR(eight.high, 0.6134, 5e-5);
  EXPECT_EQ(eight.n, 20);
}

TEST(Bootstrap, DeterministicAndSensible) {
  const std::vector<double> values{1.0, 2.0, 3.0, 4.0, 10.0};
  const Estimate a = bootstrap_mean(values, 2000, 42, 0.95);
  const Estimate b = bootstrap_mean(values, 2000, 42, 0.95);
  EXPECT_DOUBLE_EQ(a.value, 4.0);
  EXPECT_EQ(a.low, b.low);
  EXPECT_EQ(a.high, b.high);
  EXPECT_LT(a.low, a.value);
  EXPECT_GT(a.high, a.value);
  EXPECT_GE(a.low, 1.0);
  EXPECT_LE(a.high, 10.0);
  // Another seed resamples differently (20 distinct values: the percentiles move).
  std::vector<double> many;
  for (int i = 0; i < 20; ++i) many.push_back(std::sqrt(2.0 + i) * (i % 3 + 1));
  const Estimate s42 = bootstrap_mean(many, 500, 42, 0.95);
  const Estimate s43 = bootstrap_mean(many, 500, 43, 0.95);
  EXPECT_EQ(s42.value, s43.value);
  EXPECT_TRUE(s42.low != s43.low || s42.high != s43.high);
  // A constant sample has a zero-width interval.
  const std::vector<double> same{0.7, 0.7, 0.7};
  const Estimate c = bootstrap_mean(same, 100, 1, 0.95);
  EXPECT_DOUBLE_EQ(c.low, 0.7);
  EXPECT_DOUBLE_EQ(c.high, 0.7);
}

TEST(Median, OddAndEven) {
  EXPECT_DOUBLE_EQ(median({3, 1, 2}), 2.0);
  EXPECT_DOUBLE_EQ(median({4, 1, 2, 3}), 2.5);
}

EpisodeResult episode(const std::string& task, const std::string& role, const std::string& policy,
                      bool success, double ct, std::optional<double> rsp,
                      std::optional<double> dsr = std::nullopt) {
  EpisodeResult r;
  r.task = task;
  r.role = role;
  r.policy = policy;
  r.metrics.success = success;
  r.metrics.completion_time = ct;
  r.metrics.response_latency = rsp;
  r.metrics.hcs = success ? 1.0 : 0.5;
  r.metrics.collision_free = success;
  r.metrics.dsr = dsr;
  if (!success) r.metrics.primary_label = FailureLabel::kTimeout;
  return r;
}

TEST(Summarize, GroupsRatesAndSafety) {
  const std::vector<EpisodeResult> results{
      episode("stop_go", "instructor", "noop", false, 30, 1.0),
      episode("intrusion_yield", "intruder", "noop", true, 10, 0.5, 1.0),
      episode("intrusion_yield", "intruder", "noop", false, 30, 1.0, 0.0),
      episode("point_pick", "instructor", "noop", true, 12, std::nullopt),
      episode("stop_go", "instructor", "random", false, 30, 1.0),
  };
  const std::vector<GroupSummary> roles = summarize(results, GroupBy::kRole);
  ASSERT_EQ(roles.size(), 3u);
  EXPECT_EQ(roles[0].group, "instructor");
  EXPECT_EQ(roles[0].policy, "noop");
  EXPECT_EQ(roles[1].group, "intruder");
  EXPECT_EQ(roles[2].policy, "random");
  const GroupSummary& instructor = roles[0];
  EXPECT_EQ(instructor.episodes, 2);
  EXPECT_DOUBLE_EQ(instructor.csr->value, 0.5);
  EXPECT_NEAR(instructor.csr->low, wilson_interval(1, 2, kZ).low, 1e-12);
  EXPECT_DOUBLE_EQ(instructor.ct->value, 21.0);
  EXPECT_DOUBLE_EQ(instructor.ct_success->value, 12.0);
  EXPECT_EQ(instructor.rsp->n, 1);  // the episode without cues does not count
  EXPECT_DOUBLE_EQ(*instructor.rsp_median, 1.0);
  EXPECT_FALSE(instructor.dsr.has_value());
  // Safety = mean(CFR 0.5, HCS 0.75) for the instructor group.
  EXPECT_DOUBLE_EQ(*instructor.safety, (0.5 + 0.75) / 2);
  // Intruder: mean(CFR 0.5, HCS 0.75, DSR 0.5).
  EXPECT_DOUBLE_EQ(*roles[1].safety, (0.5 + 0.75 + 0.5) / 3);
  EXPECT_EQ(roles[1].failures.at("timeout"), 1);
  const std::vector<GroupSummary> tasks = summarize(results, GroupBy::kTask);
  EXPECT_EQ(tasks[0].group, "point_pick");  // tasks by role, then (without ids) by name
  EXPECT_EQ(tasks[1].group, "stop_go");
  EXPECT_EQ(tasks[2].group, "intrusion_yield");
  const std::vector<GroupSummary> overall = summarize(results, GroupBy::kOverall);
  ASSERT_EQ(overall.size(), 2u);
  EXPECT_EQ(overall[0].episodes, 4);
  // Deterministic: the same input gives the same intervals.
  EXPECT_EQ(summarize(results, GroupBy::kOverall)[0].ct->low, overall[0].ct->low);
}

TEST(Summarize, TasksInTheOrderOfTheTaskListWithTheirIds) {
  // docs/tasks.md lists I1..I5, C1..C4, X1..X4: by role, then id (I10 after I2).
  const auto with_id = [](EpisodeResult r, const std::string& id) {
    r.task_id = id;
    return r;
  };
  std::vector<EpisodeResult> results{
      with_id(episode("intrusion_yield", "intruder", "noop", true, 10, 0.5), "X1"),
      with_id(episode("handover_h2r", "collaborator", "noop", true, 10, 0.5), "C1"),
      with_id(episode("zeta", "instructor", "noop", true, 10, 0.5), "I10"),
      with_id(episode("stop_go", "instructor", "noop", false, 30, 1.0), "I4"),
      episode("my_task", "instructor", "noop", true, 10, 0.5),
  };
  results[1].metrics.critical_contact = true;
  const std::vector<GroupSummary> tasks = summarize(results, GroupBy::kTask);
  ASSERT_EQ(tasks.size(), 5u);
  std::vector<std::string> labels;
  for (const GroupSummary& s : tasks) labels.push_back(group_label(s));
  EXPECT_EQ(labels, (std::vector<std::string>{"I4 stop_go", "I10 zeta", "my_task", "C1 handover_h2r",
                                              "X1 intrusion_yield"}));
  EXPECT_EQ(tasks[3].critical_contacts, 1);
  EXPECT_EQ(tasks[0].critical_contacts, 0);
  // Role groups carry no task id.
  for (const GroupSummary& s : summarize(results, GroupBy::kRole)) EXPECT_EQ(group_label(s), s.group);
}

}  // namespace
}  // namespace hribench::eval
