// Where our physics step spends its time beyond raw mj_step, on the default scene with the
// human moving (profiles the figure `hribench bench` reports as "cost ours/raw"):
//   BM_RawStep       mj_step alone on the same compiled mjModel;
//   BM_OurStep       set_human_pose (a new pose every step) + sim::step;
//   BM_PoseHuman     set_human_pose + pose_human only (forward kinematics and mocap writes);
//
//   build/bench/step_bench --benchmark_min_time=1

#include <benchmark/benchmark.h>

#include <cmath>

#include "core/math.h"
#include "model/model.h"
#include "sim/data.h"

namespace hribench::sim {
namespace {

// A new pose per call: the right arm swinging about the shoulder's y axis.
human::SkeletonPose moving_pose(const model::Model& model, double t) {
  human::SkeletonPose pose = model.human_start;
  pose.local[human::index(human::Joint::kRightShoulder)] =
      core::axis_angle(core::Vec3::UnitY(), 0.6 * std::sin(core::kPi * t));
  return pose;
}

void BM_RawStep(benchmark::State& state) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data data = make_data(model);
  for (auto _ : state) mj_step(model.m(), data.mj.get());
}
BENCHMARK(BM_RawStep)->Unit(benchmark::kMicrosecond);

void BM_OurStep(benchmark::State& state) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data data = make_data(model);
  for (auto _ : state) {
    set_human_pose(model, data, moving_pose(model, data.time()));
    step(model, data);
  }
}
BENCHMARK(BM_OurStep)->Unit(benchmark::kMicrosecond);

void BM_PoseHuman(benchmark::State& state) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data data = make_data(model);
  double t = 0;
  for (auto _ : state) {
    set_human_pose(model, data, moving_pose(model, t));
    pose_human(model, data);
    t += model::kTimestep;
  }
}
BENCHMARK(BM_PoseHuman)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hribench::sim

BENCHMARK_MAIN();
