// Cost of each render setting on the default scene (OSMesa/llvmpipe), for docs/rendering.md:
// our settings (no shadows, reflections, skybox or MSAA; coarser shapes), then each one turned
// on alone (MuJoCo's tessellation of capsules, spheres and cylinders for the shapes), then
// MuJoCo's defaults. Shadows need lights that cast them, so the shadow rows use a scene built
// with SceneSpec::shadows = true (every other row uses the default scene).
//
//   build/bench/render_bench --benchmark_min_time=1

#include <benchmark/benchmark.h>

#include <string>

#include "model/model.h"
#include "render/renderer.h"
#include "sim/data.h"

namespace hribench::render {
namespace {

enum Variant {
  kOurs, kShadows, kReflections, kSkybox, kMsaa4, kMujocoShapes, kMujocoDefaults, kNumVariants
};

const char* variant_name(int v) {
  static const char* const kNames[kNumVariants] = {
      "ours", "+shadows", "+reflections", "+skybox", "+msaa4", "+mujoco_shapes", "mujoco_defaults"};
  return kNames[v];
}

void BM_RenderAgentview(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  const int variant = static_cast<int>(state.range(1));
  model::SceneSpec spec = model::SceneSpec::Default();
  spec.shadows = variant == kShadows || variant == kMujocoDefaults;
  const model::Model model = model::build(spec);
  sim::Data data = sim::make_data(model);
  RenderSettings settings;
  if (variant == kShadows) settings.shadows = true;
  if (variant == kReflections) settings.reflections = true;
  if (variant == kSkybox) settings.skybox = true;
  if (variant == kMsaa4) settings.multisamples = 4;
  if (variant == kMujocoShapes) {
    settings.shape_slices = RenderSettings::mujoco_defaults().shape_slices;
    settings.shape_stacks = RenderSettings::mujoco_defaults().shape_stacks;
  }
  if (variant == kMujocoDefaults) settings = RenderSettings::mujoco_defaults();
  auto renderer = make_renderer(Backend::kOsmesa, *model.m(), size, size, settings);
  Image image;
  renderer->render(*model.m(), *data.mj, model.agentview_camera, image);  // warm up
  for (auto _ : state) {
    renderer->render(*model.m(), *data.mj, model.agentview_camera, image);
    benchmark::DoNotOptimize(image.rgb.data());
  }
  state.SetLabel(variant_name(variant));
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                             benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderAgentview)
    ->ArgsProduct({{128, 224}, {kOurs, kShadows, kReflections, kSkybox, kMsaa4, kMujocoShapes, kMujocoDefaults}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace hribench::render

BENCHMARK_MAIN();
