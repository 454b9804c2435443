#include "eval/parallel.h"

#include <gtest/gtest.h>

#include <mutex>
#include <set>
#include <stdexcept>

#include "eval/episode_builder.h"
#include "eval/report.h"

namespace hribench::eval {
namespace {

// A deterministic episode per job: the robot stops later for higher jobs.
EpisodeResult score_job(size_t job) {
  testing::EpisodeBuilder b(4.0);
  b.move_x(0.0, 1.0 + 0.05 * static_cast<double>(job % 20), 0.1).event(1.0, "stop.stroke");
  if (job % 3 == 0) b.predicate("success", 3.0, 4.0);
  EpisodeLog log = b.log();
  log.seed = job;
  ScenarioContract contract;
  contract.cues.push_back({"stop", "stop.stroke", CueKind::kStop, 0.6, std::nullopt});
  return make_result(log, compute_metrics(contract, log));
}

std::string results_text(const std::vector<EpisodeResult>& results) {
  RunResults run;
  run.episodes = results;
  return results_to_json(run).dump();
}

TEST(RunJobs, SameResultsWithOneAndTwoThreads) {
  std::set<size_t> seen;
  const auto one = run_jobs(
      40, 1, [](size_t job, int) { return score_job(job); },
      [&](size_t job, const EpisodeResult&) { seen.insert(job); });
  EXPECT_EQ(seen.size(), 40u);
  seen.clear();
  // The jobs run concurrently; only the bookkeeping of which worker ran them is locked.
  std::mutex workers_mutex;
  std::set<int> workers;
  const auto two = run_jobs(
      40, 2,
      [&](size_t job, int worker) {
        EpisodeResult result = score_job(job);
        std::lock_guard lock(workers_mutex);
        workers.insert(worker);
        return result;
      },
      [&](size_t job, const EpisodeResult&) { EXPECT_TRUE(seen.insert(job).second); });
  EXPECT_EQ(seen.size(), 40u);
  // Job order, whatever the completion order, and the same results as one thread.
  ASSERT_EQ(two.size(), 40u);
  for (size_t i = 0; i < two.size(); ++i) EXPECT_EQ(two[i].seed, i);
  EXPECT_EQ(results_text(one), results_text(two));
  ASSERT_FALSE(workers.empty());
  EXPECT_GE(*workers.begin(), 0);
  EXPECT_LE(*workers.rbegin(), 1);
}

TEST(RunJobs, FirstErrorIsRethrown) {
  EXPECT_THROW(run_jobs(
                   10, 2,
                   [](size_t job, int) -> EpisodeResult {
                     if (job == 3) throw std::runtime_error("job 3");
                     return score_job(job);
                   },
                   nullptr),
               std::runtime_error);
  EXPECT_TRUE(run_jobs(0, 4, [](size_t job, int) { return score_job(job); }, nullptr).empty());
}

TEST(EpisodeKey, NamesTheEpisode) {
  EXPECT_EQ(episode_key("stop_go", "noop", "ab12", 7), "stop_go|noop|ab12|7");
  EpisodeResult r = score_job(5);
  EXPECT_EQ(episode_key(r), "test_task|noop|0123abcd|5");
}

}  // namespace
}  // namespace hribench::eval
