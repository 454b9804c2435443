#include "eval/ranks.h"

// MPI's C interface only (not the removed C++ bindings, which need a library of their own).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <map>
#include <string>
#include <thread>

#include <fmt/format.h>

#include "core/errors.h"

namespace hribench::eval {
namespace {

constexpr uint64_t kNone = UINT64_MAX;  // "no job": nothing finished, or nothing more to run
constexpr int kAskTag = 1;              // worker thread -> rank 0
constexpr int kAnswerTag = 2;           // rank 0 -> worker thread t: tag kAnswerTag + t

// The process count mpirun (Open MPI) or a PMI launcher (MPICH, Slurm's srun) announces.
int launched_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* value = std::getenv(name);
    if (value != nullptr) return std::atoi(value);
  }
  return 1;
}

// A request: the asking thread, the job it finished (kNone: none) and that job's episode line.
std::string ask_message(uint32_t thread, uint64_t finished, const std::string& line) {
  std::string bytes(sizeof thread + sizeof finished, '\0');
  std::memcpy(bytes.data(), &thread, sizeof thread);
  std::memcpy(bytes.data() + sizeof thread, &finished, sizeof finished);
  return bytes + line;
}

}  // namespace

Ranks mpi_ranks() {
  static const Ranks ranks = [] {
    if (launched_size() <= 1) return Ranks{};
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_MULTIPLE, &provided);
    std::atexit([] {
      int finalized = 0;
      MPI_Finalized(&finalized);
      if (finalized == 0) MPI_Finalize();
    });
    if (provided < MPI_THREAD_MULTIPLE) {
      throw core::InputError("mpirun", "an MPI library with MPI_THREAD_MULTIPLE",
                             fmt::format("thread level {}", provided));
    }
    Ranks r;
    MPI_Comm_rank(MPI_COMM_WORLD, &r.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &r.size);
    return r;
  }();
  return ranks;
}

void hand_out_jobs(const std::vector<size_t>& job_ids, int threads_per_rank, const std::function<bool()>& stop,
                   const std::function<void(size_t, std::string_view reply)>& done) {
  const Ranks ranks = mpi_ranks();
  std::map<uint64_t, size_t> position;
  for (size_t i = 0; i < job_ids.size(); ++i) position[job_ids[i]] = i;
  const int threads = (ranks.size - 1) * threads_per_rank;
  int retired = 0;
  size_t next = 0;
  std::exception_ptr error;
  while (retired < threads) {
    MPI_Status status;
    MPI_Probe(MPI_ANY_SOURCE, kAskTag, MPI_COMM_WORLD, &status);
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    std::string bytes(static_cast<size_t>(count), '\0');
    MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, kAskTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    uint32_t thread = 0;
    uint64_t finished = kNone;
    HRIB_CHECK(bytes.size() >= sizeof thread + sizeof finished) << "a request of " << bytes.size() << " bytes";
    std::memcpy(&thread, bytes.data(), sizeof thread);
    std::memcpy(&finished, bytes.data() + sizeof thread, sizeof finished);
    if (finished != kNone && !error) {
      try {
        done(position.at(finished), std::string_view(bytes).substr(sizeof thread + sizeof finished));
      } catch (...) {
        error = std::current_exception();
      }
    }
    uint64_t job = kNone;
    if (!error && next < job_ids.size() && !stop()) {
      job = job_ids[next++];
    } else {
      ++retired;
    }
    MPI_Send(&job, sizeof job, MPI_BYTE, status.MPI_SOURCE, kAnswerTag + static_cast<int>(thread), MPI_COMM_WORLD);
  }
  if (error) std::rethrow_exception(error);
}

ReleaseWorkersOnError::~ReleaseWorkersOnError() {
  if (armed_ && mpi_ranks().distributed()) {
    hand_out_jobs({}, threads_, [] { return true; }, [](size_t, std::string_view) {});
  }
}

void serve_jobs(int threads, const std::function<std::string(size_t job_id, int worker)>& run) {
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t) {
    workers.emplace_back([t, &run] {
      uint64_t finished = kNone;
      std::string line;  // the reply of `finished`
      for (;;) {
        const std::string ask = ask_message(static_cast<uint32_t>(t), finished, line);
        MPI_Send(ask.data(), static_cast<int>(ask.size()), MPI_BYTE, 0, kAskTag, MPI_COMM_WORLD);
        uint64_t job = kNone;
        MPI_Recv(&job, sizeof job, MPI_BYTE, 0, kAnswerTag + t, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (job == kNone) return;
        line = run(static_cast<size_t>(job), t);
        finished = job;
      }
    });
  }
  for (std::thread& w : workers) w.join();
}

}  // namespace hribench::eval
