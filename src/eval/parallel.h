#pragma once
// Many episodes on a thread pool (issue 5): results are ordered by job index whatever the
// thread count, so a run with 1 and with N threads writes the same results. Each worker has
// an index in [0, threads) so callers keep one sim::Data (and one policy) per worker.

#include <functional>
#include <string>
#include <vector>

#include "eval/aggregate.h"

namespace hribench::eval {

// Runs run(job, worker) for job = 0 .. jobs-1 on `threads` >= 1 threads and returns the
// results in job order. done(job, result) is called once per job as it finishes (serialized
// by a mutex; completion order), e.g. to append the episode to a JSON-lines file and update a
// progress line. If a call throws, no new jobs start, and the first exception is rethrown once
// the running ones have finished.
std::vector<EpisodeResult> run_jobs(size_t jobs, int threads,
                                    const std::function<EpisodeResult(size_t job, int worker)>& run,
                                    const std::function<void(size_t job, const EpisodeResult&)>& done);

// Identity of an episode within a run (task, policy, spec hash, seed): --resume skips the jobs
// whose key is already in the run's episode file.
std::string episode_key(const std::string& task, const std::string& policy,
                        const std::string& spec_hash, uint64_t seed);
std::string episode_key(const EpisodeResult& result);

}  // namespace hribench::eval
