// Candidates validated per second by the generation pipeline (issue 7, done-when 5): each
// iteration judges one candidate of every task (gen::judge_candidate: sample + all filters),
// with and without the executability rollout, on 1 thread and on all cores. The counter
// `candidates_per_s` is the rate (wall clock).
//
//   build/bench/gen_bench                        # both modes, 1 thread and all cores
//   build/bench/gen_bench --benchmark_filter=none
//
// The rollout uses the policy named by HRIB_GEN_BENCH_POLICY (default "oracle"); when it is
// not registered that benchmark is skipped with a message.

#include <benchmark/benchmark.h>

#include <atomic>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "gen/generate.h"
#include "gen/pool.h"
#include "policy/registry.h"
#include "script/check.h"

namespace hribench::gen {
namespace {

struct Tasks {
  std::vector<script::Scenario> scenarios;
  std::vector<std::string> names;
};

const Tasks& tasks() {
  static const Tasks t = [] {
    Tasks all;
    for (const std::string& file : resolve_task_scripts("all")) {
      all.scenarios.push_back(script::load_scenario(file));
      all.names.push_back(all.scenarios.back().task);
    }
    return all;
  }();
  return t;
}

// Judges candidates index, index + 1, ... of every task on `threads` threads.
void judge_batch(size_t first, int threads, const FilterOptions& filters) {
  const Tasks& t = tasks();
  std::atomic<size_t> next{0};
  const auto worker = [&] {
    for (size_t job = next++; job < t.names.size(); job = next++) {
      benchmark::DoNotOptimize(judge_candidate(t.scenarios[job], t.names[job], first, 0, model::kDefaultRobot, filters));
    }
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (std::thread& th : pool) th.join();
}

void run(benchmark::State& state, const std::string& executable_by) {
  if (executable_by != "none") {
    try {
      policy::make_policy(executable_by);
    } catch (const std::exception& e) {
      state.SkipWithError(("policy not available: " + std::string(e.what())).c_str());
      return;
    }
  }
  const int threads = static_cast<int>(state.range(0));
  FilterOptions filters;
  filters.executable_by = executable_by;
  size_t batch = 0, judged = 0;
  for (auto _ : state) {
    judge_batch(batch++ * static_cast<size_t>(threads), threads, filters);
    judged += tasks().names.size();
  }
  state.counters["candidates_per_s"] =
      benchmark::Counter(static_cast<double>(judged), benchmark::Counter::kIsRate);
  state.counters["threads"] = threads;
}

void BM_Validate_none(benchmark::State& state) { run(state, "none"); }
void BM_Validate_rollout(benchmark::State& state) {
  const char* policy = std::getenv("HRIB_GEN_BENCH_POLICY");
  run(state, policy != nullptr ? policy : "oracle");
}

int all_cores() { return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())); }

BENCHMARK(BM_Validate_none)->Arg(1)->Arg(all_cores())->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2);
BENCHMARK(BM_Validate_rollout)->Arg(1)->Arg(all_cores())->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
}  // namespace hribench::gen

BENCHMARK_MAIN();
