#include "eval/aggregate.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <tuple>

#include "core/rng.h"

namespace hribench::eval {

EpisodeResult make_result(const EpisodeLog& log, EpisodeMetrics metrics) {
  EpisodeResult r;
  r.task = log.task;
  r.role = log.role;
  r.policy = log.policy;
  r.robot = log.robot;
  r.spec_hash = log.spec_hash;
  r.seed = log.seed;
  r.status = log.status;
  r.status_reason = log.status_reason;
  r.metrics = std::move(metrics);
  return r;
}

Estimate wilson_interval(int successes, int n, double z) {
  HRIB_CHECK(n > 0 && successes >= 0 && successes <= n) << successes << "/" << n;
  const double nn = n;
  const double p = successes / nn;
  const double z2 = z * z;
  const double denominator = 1.0 + z2 / nn;
  const double centre = (p + z2 / (2.0 * nn)) / denominator;
  const double half = z / denominator * std::sqrt(p * (1.0 - p) / nn + z2 / (4.0 * nn * nn));
  return Estimate{p, std::max(0.0, centre - half), std::min(1.0, centre + half), n};
}

namespace {

double mean(std::span<const double> values) {
  double sum = 0;
  for (const double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

// Linear interpolation between order statistics of sorted values, q in [0, 1].
double percentile(const std::vector<double>& sorted, double q) {
  const double position = q * static_cast<double>(sorted.size() - 1);
  const size_t below = static_cast<size_t>(std::floor(position));
  const size_t above = std::min(below + 1, sorted.size() - 1);
  const double frac = position - static_cast<double>(below);
  return sorted[below] + frac * (sorted[above] - sorted[below]);
}

}  // namespace

Estimate bootstrap_mean(std::span<const double> values, int resamples, uint64_t seed,
                        double confidence) {
  HRIB_CHECK(!values.empty() && resamples > 0);
  const double m = mean(values);
  const int n = static_cast<int>(values.size());
  core::Rng rng(seed);
  std::vector<double> means(static_cast<size_t>(resamples));
  for (double& resampled : means) {
    double sum = 0;
    for (int i = 0; i < n; ++i) sum += values[static_cast<size_t>(rng.uniform_int(0, n - 1))];
    resampled = sum / n;
  }
  std::sort(means.begin(), means.end());
  const double alpha = 1.0 - confidence;
  return Estimate{m, percentile(means, alpha / 2), percentile(means, 1.0 - alpha / 2), n};
}

double median(std::vector<double> values) {
  HRIB_CHECK(!values.empty());
  std::sort(values.begin(), values.end());
  const size_t mid = values.size() / 2;
  return values.size() % 2 == 1 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

namespace {

int role_rank(const std::string& role) {
  if (role == "instructor") return 0;
  if (role == "collaborator") return 1;
  if (role == "intruder") return 2;
  return 3;
}

std::string group_of(const EpisodeResult& r, GroupBy by) {
  switch (by) {
    case GroupBy::kTask:
      return r.task;
    case GroupBy::kRole:
      return r.role;
    case GroupBy::kOverall:
      return "overall";
  }
  return "";
}

using Getter = std::function<std::optional<double>(const EpisodeMetrics&)>;

// The applicable values of one metric over a group's episodes.
std::vector<double> collect(const std::vector<const EpisodeResult*>& episodes, const Getter& get) {
  std::vector<double> values;
  for (const EpisodeResult* r : episodes) {
    if (const std::optional<double> v = get(r->metrics)) values.push_back(*v);
  }
  return values;
}

GroupSummary summarize_group(const std::string& group, const std::string& policy,
                             const std::vector<const EpisodeResult*>& episodes,
                             const MetricConstants& c) {
  GroupSummary s;
  s.group = group;
  s.policy = policy;
  s.episodes = static_cast<int>(episodes.size());
  const core::Rng streams(c.bootstrap_seed);
  const auto continuous = [&](const char* name, const Getter& get) -> std::optional<Estimate> {
    const std::vector<double> values = collect(episodes, get);
    if (values.empty()) return std::nullopt;
    // Each (policy, group, metric) has its own stream: independent of the other summaries.
    const uint64_t seed = streams.split(policy).split(group).split(name).key();
    return bootstrap_mean(values, c.bootstrap_resamples, seed, c.confidence);
  };
  const auto rate = [&](const Getter& get) -> std::optional<Estimate> {
    const std::vector<double> values = collect(episodes, get);
    if (values.empty()) return std::nullopt;
    const auto hits = std::count_if(values.begin(), values.end(), [](double v) { return v >= 0.5; });
    return wilson_interval(static_cast<int>(hits), static_cast<int>(values.size()), c.wilson_z());
  };
  s.csr = rate([](const EpisodeMetrics& m) { return m.success ? 1.0 : 0.0; });
  s.ct = continuous("ct", [](const EpisodeMetrics& m) { return m.completion_time; });
  s.ct_success = continuous("ct_success", [](const EpisodeMetrics& m) {
    return m.success ? std::optional<double>(m.completion_time) : std::nullopt;
  });
  s.ir = continuous("ir", [](const EpisodeMetrics& m) { return m.idle_ratio; });
  const Getter rsp = [](const EpisodeMetrics& m) { return m.response_latency; };
  s.rsp = continuous("rsp", rsp);
  if (const std::vector<double> values = collect(episodes, rsp); !values.empty()) {
    s.rsp_median = median(values);
  }
  s.tsync = continuous("tsync", [](const EpisodeMetrics& m) { return m.tsync; });
  s.oc = continuous("oc", [](const EpisodeMetrics& m) { return m.order_compliance; });
  s.cfr = rate([](const EpisodeMetrics& m) { return m.collision_free ? 1.0 : 0.0; });
  s.hcs = continuous("hcs", [](const EpisodeMetrics& m) { return m.hcs; });
  s.cir = rate([](const EpisodeMetrics& m) { return m.cir; });
  s.dsr = rate([](const EpisodeMetrics& m) { return m.dsr; });
  s.r_idle = continuous("r_idle", [](const EpisodeMetrics& m) { return m.r_idle; });
  s.h_idle = continuous("h_idle", [](const EpisodeMetrics& m) { return m.h_idle; });
  s.c_act = continuous("c_act", [](const EpisodeMetrics& m) { return m.c_act; });
  s.f_del = continuous("f_del", [](const EpisodeMetrics& m) { return m.f_del; });
  // Safety: the mean of the components that apply to this group.
  double sum = 0;
  int count = 0;
  for (const auto& part : {s.cfr, s.hcs, s.cir, s.dsr}) {
    if (!part) continue;
    sum += part->value;
    ++count;
  }
  if (count > 0) s.safety = sum / count;
  for (const EpisodeResult* r : episodes) {
    if (r->metrics.primary_label) ++s.failures[std::string(to_string(*r->metrics.primary_label))];
    if (r->metrics.critical_contact) ++s.critical_contacts;
  }
  return s;
}

}  // namespace

std::string group_label(const GroupSummary& s) {
  return s.task_id.empty() ? s.group : s.task_id + " " + s.group;
}

std::vector<GroupSummary> summarize(const std::vector<EpisodeResult>& results, GroupBy by,
                                    const MetricConstants& c) {
  // Policies in order of first appearance; groups in the documented order. A group's sort key
  // is its role's rank, then (tasks) its id, then its name; ids without a value sort last.
  struct Group {
    std::string name;
    int rank = 0;
    std::string task_id;
  };
  std::vector<std::string> policies;
  std::vector<Group> groups;
  for (const EpisodeResult& r : results) {
    if (std::find(policies.begin(), policies.end(), r.policy) == policies.end()) {
      policies.push_back(r.policy);
    }
    const std::string g = group_of(r, by);
    if (std::none_of(groups.begin(), groups.end(), [&](const Group& x) { return x.name == g; })) {
      groups.push_back({g, role_rank(by == GroupBy::kOverall ? g : r.role),
                        by == GroupBy::kTask ? r.task_id : std::string()});
    }
  }
  std::sort(groups.begin(), groups.end(), [](const Group& a, const Group& b) {
    const auto key = [](const Group& g) {
      return std::make_tuple(g.rank, g.task_id.empty(), g.task_id.size(), g.task_id, g.name);
    };
    return key(a) < key(b);
  });
  std::vector<GroupSummary> out;
  for (const std::string& policy : policies) {
    for (const Group& group : groups) {
      std::vector<const EpisodeResult*> episodes;
      for (const EpisodeResult& r : results) {
        if (r.policy == policy && group_of(r, by) == group.name) episodes.push_back(&r);
      }
      if (episodes.empty()) continue;
      out.push_back(summarize_group(group.name, policy, episodes, c));
      out.back().task_id = group.task_id;
    }
  }
  return out;
}

}  // namespace hribench::eval
