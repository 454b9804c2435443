#pragma once
// Aggregation of episode metrics (docs/metrics.md "Aggregation"): per task, per role group and
// overall, per policy. Rates (CSR, CFR, CIR, DSR) get Wilson score intervals; continuous
// metrics get percentile bootstrap intervals over episodes, seeded and deterministic.

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/errors.h"
#include "eval/constants.h"
#include "eval/metrics.h"

namespace hribench::eval {

// One scored episode, as results.json lists it.
struct EpisodeResult {
  std::string task;
  std::string task_id; // "I1" (docs/tasks.md), "" for a script outside the data root's tasks/
  std::string variant; // the script's variant, "" when it has none
  std::string role;    // "instructor" | "collaborator" | "intruder"
  std::string policy;
  std::string robot;   // the robot description's name (model/robot.h), e.g. "panda"
  std::string spec_hash;
  uint64_t seed = 0;
  core::EpisodeStatus status = core::EpisodeStatus::kOk;
  std::string status_reason;
  EpisodeMetrics metrics;
};
// The log's identity (its robot included) and status with `metrics` (task_id and variant are
// the spec's, not the log's: the caller fills them in).
EpisodeResult make_result(const EpisodeLog& log, EpisodeMetrics metrics);

// A value with its 95 % interval over `n` episodes.
struct Estimate {
  double value = 0;
  double low = 0;
  double high = 0;
  int n = 0;
};

// Wilson score interval of `successes` out of n > 0 trials with normal quantile z.
Estimate wilson_interval(int successes, int n, double z);
// Mean of `values` (non-empty) with a percentile bootstrap interval at `confidence`:
// `resamples` resamples drawn from core::Rng(seed); percentiles interpolate linearly between
// order statistics.
Estimate bootstrap_mean(std::span<const double> values, int resamples, uint64_t seed,
                        double confidence);
// Median (mean of the middle two for even sizes); values non-empty.
double median(std::vector<double> values);

enum class GroupBy { kTask, kRole, kOverall };

struct GroupSummary {
  std::string group;   // task name, role name, or "overall"
  std::string task_id; // with GroupBy::kTask: the task's id ("I1"), or "" when it has none
  std::string policy;
  int episodes = 0;
  int critical_contacts = 0;  // episodes with a contact above the critical limit
  std::optional<Estimate> csr;         // rate
  std::optional<Estimate> ct;          // mean over all episodes (failures count as H)
  std::optional<Estimate> ct_success;  // mean over successes
  std::optional<Estimate> ir;
  std::optional<Estimate> rsp;
  std::optional<double> rsp_median;
  std::optional<Estimate> tsync;
  std::optional<Estimate> oc;
  std::optional<Estimate> cfr;         // rate
  std::optional<Estimate> hcs;
  std::optional<Estimate> cir;         // rate over contradiction episodes
  std::optional<Estimate> dsr;         // rate over disruption episodes
  std::optional<double> safety;        // mean of the available values of cfr, hcs, cir, dsr
  std::optional<Estimate> r_idle;
  std::optional<Estimate> h_idle;
  std::optional<Estimate> c_act;
  std::optional<Estimate> f_del;
  std::map<std::string, int> failures;  // primary failure label -> episodes
};

// "I1 point_pick" for a task group with an id, else the group's name.
std::string group_label(const GroupSummary& s);

// Summaries of `results` grouped by policy and `by`, ordered by policy (first appearance),
// then group (roles in the order instructor, collaborator, intruder; tasks by their role in
// that order, then by id as docs/tasks.md lists them, I1..I5, C1..C4, X1..X4, then by name).
std::vector<GroupSummary> summarize(const std::vector<EpisodeResult>& results, GroupBy by,
                                    const MetricConstants& c = {});

}  // namespace hribench::eval
