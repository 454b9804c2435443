#include "eval/parallel.h"

#include <atomic>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

#include "core/errors.h"

namespace hribench::eval {

std::vector<EpisodeResult> run_jobs(size_t jobs, int threads,
                                    const std::function<EpisodeResult(size_t job, int worker)>& run,
                                    const std::function<void(size_t job, const EpisodeResult&)>& done) {
  HRIB_CHECK(threads >= 1) << "threads=" << threads;
  std::vector<std::optional<EpisodeResult>> slots(jobs);
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  std::mutex mutex;
  std::exception_ptr error;
  // Each worker takes the next job index until none is left (or one failed).
  const auto work = [&](int worker) {
    while (!failed.load()) {
      const size_t job = next.fetch_add(1);
      if (job >= jobs) return;
      try {
        EpisodeResult result = run(job, worker);
        std::lock_guard lock(mutex);
        if (done) done(job, result);
        slots[job] = std::move(result);
      } catch (...) {
        std::lock_guard lock(mutex);
        if (!error) error = std::current_exception();
        failed.store(true);
      }
    }
  };
  std::vector<std::thread> pool;
  const int extra = static_cast<int>(std::min<size_t>(static_cast<size_t>(threads), jobs)) - 1;
  for (int w = 1; w <= extra; ++w) pool.emplace_back(work, w);
  work(0);
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  std::vector<EpisodeResult> results;
  results.reserve(jobs);
  for (std::optional<EpisodeResult>& slot : slots) results.push_back(std::move(*slot));
  return results;
}

std::string episode_key(const std::string& task, const std::string& policy,
                        const std::string& spec_hash, uint64_t seed) {
  return task + "|" + policy + "|" + spec_hash + "|" + std::to_string(seed);
}

std::string episode_key(const EpisodeResult& result) {
  return episode_key(result.task, result.policy, result.spec_hash, result.seed);
}

}  // namespace hribench::eval
