#pragma once
// A run spread over MPI ranks (docs/scale.md "MPI"): `mpirun -np N hribench eval ...` starts N
// copies of one command. Rank 0 plans the run as a single process does, hands the jobs out one
// at a time to the worker threads of ranks 1..N-1 as they ask (so a slow episode holds up no
// other), takes each finished episode back and appends it, and writes the results; the other
// ranks only run episodes. Outside mpirun, or with one rank, nothing here runs and MPI is never
// initialised, so the binary needs no mpirun.
//
// Messages (MPI_BYTE, MPI_COMM_WORLD): a worker thread's request to rank 0 carries the job it
// finished (if any) with its reply (for `eval`, the episode's line of episodes.jsonl:
// eval/report.h episode_to_json, exact for every double), and rank 0 answers that thread with
// its next job or "none". Episode logs and videos are written by the rank that ran the episode,
// into OUT/logs and OUT/videos: the ranks must share OUT's file system, as on a cluster's shared
// disk.

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace hribench::eval {

// This process's place in an mpirun launch.
struct Ranks {
  int rank = 0;
  int size = 1;
  bool distributed() const { return size > 1; }
};

// Outside mpirun (no OMPI_COMM_WORLD_SIZE or PMI_SIZE above 1 in the environment): {0, 1},
// without touching MPI. Under mpirun with several processes: initialises MPI once (thread level
// MPI_THREAD_MULTIPLE; it is finalised at exit) and returns this process's rank and the size.
// Throws core::InputError if MPI cannot give that thread level.
Ranks mpi_ranks();

// Rank 0: hands out the jobs `job_ids` (ids the workers' `run` understands) to the
// `threads_per_rank` worker threads of each other rank, one at a time as they ask, and calls
// done(index into job_ids, the job's reply) on this thread as each reply comes back. Stops
// handing out once stop() is true or `done` threw; returns (or rethrows `done`'s exception)
// after every worker thread has been told there is nothing more.
void hand_out_jobs(const std::vector<size_t>& job_ids, int threads_per_rank, const std::function<bool()>& stop,
                   const std::function<void(size_t, std::string_view reply)>& done);

// Rank 0 of a distributed run: until disarmed, its destruction tells every worker thread of the
// other ranks that there is nothing to run, so that a run that fails before its hand-out (another
// run in --out, say) ends every rank instead of leaving them waiting. Does nothing outside
// mpirun.
class ReleaseWorkersOnError {
 public:
  explicit ReleaseWorkersOnError(int threads_per_rank) : threads_(threads_per_rank) {}
  ReleaseWorkersOnError(const ReleaseWorkersOnError&) = delete;
  ReleaseWorkersOnError& operator=(const ReleaseWorkersOnError&) = delete;
  ~ReleaseWorkersOnError();
  void disarm() { armed_ = false; }

 private:
  int threads_;
  bool armed_ = true;
};

// Ranks 1..N-1: `threads` worker threads ask rank 0 for jobs and run them as run(job id,
// worker index), whose value is the job's reply, until told there are none.
void serve_jobs(int threads, const std::function<std::string(size_t job_id, int worker)>& run);

}  // namespace hribench::eval
