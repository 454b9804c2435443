// The runner's cost against raw physics (issue 5: "the runner's cost <= 1.25x raw physics
// steps, measured in one run"), on the default scene:
//   BM_RunnerVsRawStep  each iteration runs one noop episode with state observations (2 s at
//                       the default 50 ms control step: 1000 physics steps, 40 policy queries,
//                       41 recorded steps) and then the same number of raw mj_step calls on the
//                       same compiled mjModel. The iteration time is the episode's; the counters
//                       give both totals and their ratio `runner_over_raw`.
//
//   build/bench/runner_bench --benchmark_min_time=2

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>

#include "eval/runner.h"
#include "model/model.h"
#include "policy/builtin.h"
#include "sim/data.h"

namespace hribench::eval {
namespace {

// The noop policy, asking for human keypoints and object poses every query.
class StateNoopPolicy : public policy::NoopPolicy {
 public:
  policy::PolicySpec spec() const override {
    policy::PolicySpec s = NoopPolicy::spec();
    s.state_track = true;
    return s;
  }
};

void BM_RunnerVsRawStep(benchmark::State& state) {
  const model::Model model = model::build(model::SceneSpec::Default());
  sim::Data data = sim::make_data(model);
  sim::Data raw = sim::make_data(model);
  StateNoopPolicy noop;
  StandingHumanDriver driver;
  RunOptions options;
  options.horizon = 2.0;
  options.stop_on_success = false;
  const EpisodeSetup setup{"bench", "instructor", "0", 0, "stay", "noop"};
  const int physics_steps =
      static_cast<int>(std::lround(options.horizon / model::kTimestep));
  double runner_s = 0;
  double raw_s = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const EpisodeLog log = run_episode(model, data, noop, driver, setup, options);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(log.steps.size());
    mj_resetData(model.m(), raw.mj.get());
    for (int i = 0; i < physics_steps; ++i) mj_step(model.m(), raw.mj.get());
    const auto t2 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(raw.mj->time);
    const double episode = std::chrono::duration<double>(t1 - t0).count();
    runner_s += episode;
    raw_s += std::chrono::duration<double>(t2 - t1).count();
    state.SetIterationTime(episode);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["runner_ms"] = 1e3 * runner_s / n;
  state.counters["raw_ms"] = 1e3 * raw_s / n;
  state.counters["physics_steps"] = physics_steps;
  state.counters["runner_over_raw"] = raw_s > 0 ? runner_s / raw_s : 0.0;
}
BENCHMARK(BM_RunnerVsRawStep)->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hribench::eval

BENCHMARK_MAIN();
