// `hribench bench [--json FILE] [--seconds S] [--threads N] [--backend B]`: speed of the full
// default scene with the human moving, like MuJoCo's testspeed. Every figure of ours stands
// beside the raw MuJoCo rate on the SAME compiled mjModel, measured in the same run with the
// two interleaved (raw block, our block, raw block, ...) so machine noise hits both alike:
//   physics: our step (set_human_pose + sim::step) vs raw mj_step replaying the same mocap
//            trajectory, on 1 thread and on N threads (one Data per thread, a shared Model);
//   render:  our Renderer::render vs raw mjv_updateScene + mjr_render + mjr_readPixels on the
//            same mjrContext and mjvScene, per camera at 128x128 and 224x224.
// Wall-clock figures are measurements, never results: nothing else reads them.
// `hribench bench --episodes [--tasks L] [--policies L] [--seeds N] [--repeats R] ...`: real
// task episodes instead (cli/episode_bench.h).

#include <algorithm>
#include <barrier>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli/command.h"
#include "cli/episode_bench.h"
#include "core/errors.h"
#include "core/math.h"
#include "core/version.h"
#include "human/skeleton.h"
#include "model/model.h"
#include "render/renderer.h"
#include "sim/data.h"

namespace hribench::cli {
namespace {

using Clock = std::chrono::steady_clock;

struct BenchOptions {
  std::string json;
  double seconds = 1.0;  // wall seconds per measurement (ours and raw together)
  int threads = 0;       // 0: all cores
  std::string backend = "osmesa";
};

constexpr int kRepetitions = 10;      // interleaved raw/our block pairs per measurement
constexpr double kSwingPeriod = 2.0;  // s, period of the human's arm swing

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The cost ratio ours/raw of a measurement: the median over its interleaved block pairs of
// (our time per unit) / (raw time per unit), robust to bursts of load from other processes.
double median_ratio(std::vector<double> ratios) {
  if (ratios.empty()) return 0;
  std::sort(ratios.begin(), ratios.end());
  const size_t n = ratios.size();
  return n % 2 == 1 ? ratios[n / 2] : 0.5 * (ratios[n / 2 - 1] + ratios[n / 2]);
}

// The human's pose at time t: standing at its start pose, arms swinging in opposition about
// the shoulders' y axes, elbows bending with the swing. Periodic with kSwingPeriod.
human::SkeletonPose swing_pose(const model::Model& model, double t) {
  human::SkeletonPose pose = model.human_start;
  const double phase = 2 * core::kPi * t / kSwingPeriod;
  const core::Vec3 y = core::Vec3::UnitY();
  const double swing = 0.6 * std::sin(phase);
  pose.local[human::index(human::Joint::kLeftShoulder)] = core::axis_angle(y, -swing);
  pose.local[human::index(human::Joint::kRightShoulder)] = core::axis_angle(y, swing);
  pose.local[human::index(human::Joint::kLeftElbow)] =
      core::axis_angle(y, -0.4 * (1 + std::sin(phase)));
  pose.local[human::index(human::Joint::kRightElbow)] =
      core::axis_angle(y, -0.4 * (1 - std::sin(phase)));
  return pose;
}

// The mocap trajectory of one swing period, one row per physics step, so the raw loop replays
// exactly the motion our loop produces, with a memcpy instead of our pose pipeline.
struct MocapTrajectory {
  int steps = 0;
  int nmocap = 0;
  std::vector<double> pos;   // steps x nmocap x 3
  std::vector<double> quat;  // steps x nmocap x 4
};

MocapTrajectory record_mocap(const model::Model& model) {
  const mjModel* m = model.m();
  MocapTrajectory trajectory;
  trajectory.nmocap = m->nmocap;
  trajectory.steps = static_cast<int>(std::lround(kSwingPeriod / m->opt.timestep));
  if (m->nmocap == 0 || !model.has_human) return trajectory;
  sim::Data scratch = sim::make_data(model);
  trajectory.pos.resize(static_cast<size_t>(trajectory.steps * m->nmocap * 3));
  trajectory.quat.resize(static_cast<size_t>(trajectory.steps * m->nmocap * 4));
  for (int i = 0; i < trajectory.steps; ++i) {
    sim::set_human_pose(model, scratch, swing_pose(model, i * m->opt.timestep));
    std::memcpy(&trajectory.pos[static_cast<size_t>(i * m->nmocap * 3)], scratch.mj->mocap_pos,
                sizeof(double) * static_cast<size_t>(m->nmocap * 3));
    std::memcpy(&trajectory.quat[static_cast<size_t>(i * m->nmocap * 4)], scratch.mj->mocap_quat,
                sizeof(double) * static_cast<size_t>(m->nmocap * 4));
  }
  return trajectory;
}

// One worker of the physics measurement: its own pair of Data (ours and raw) on the shared
// Model, stepping in blocks between barriers.
struct PhysicsWorker {
  sim::Data ours;
  mjData* raw = nullptr;
  int raw_step = 0;  // index into the mocap trajectory
  double our_seconds = 0;
  double raw_seconds = 0;
  long our_steps = 0;
  long raw_steps = 0;
  double last_raw_block = 0;   // seconds of the last raw block
  std::vector<double> ratios;  // per block pair: our time / raw time (equal step counts)

  explicit PhysicsWorker(const model::Model& model) : ours(sim::make_data(model)) {
    raw = mj_makeData(model.m());
    mj_copyData(raw, model.m(), ours.mj.get());
  }
  ~PhysicsWorker() { mj_deleteData(raw); }
  PhysicsWorker(const PhysicsWorker&) = delete;
  PhysicsWorker& operator=(const PhysicsWorker&) = delete;

  void run_ours(const model::Model& model, long steps) {
    const Clock::time_point start = Clock::now();
    for (long i = 0; i < steps; ++i) {
      sim::set_human_pose(model, ours, swing_pose(model, ours.mj->time));
      sim::step(model, ours);
    }
    const double elapsed = seconds_since(start);
    our_seconds += elapsed;
    our_steps += steps;
    if (last_raw_block > 0) ratios.push_back(elapsed / last_raw_block);
  }
  void run_raw(const model::Model& model, const MocapTrajectory& trajectory, long steps) {
    const mjModel* m = model.m();
    const size_t pos_size = static_cast<size_t>(trajectory.nmocap * 3);
    const size_t quat_size = static_cast<size_t>(trajectory.nmocap * 4);
    const Clock::time_point start = Clock::now();
    for (long i = 0; i < steps; ++i) {
      if (!trajectory.pos.empty()) {
        const size_t row = static_cast<size_t>(raw_step % trajectory.steps);
        std::memcpy(raw->mocap_pos, &trajectory.pos[row * pos_size], sizeof(double) * pos_size);
        std::memcpy(raw->mocap_quat, &trajectory.quat[row * quat_size],
                    sizeof(double) * quat_size);
      }
      mj_step(m, raw);
      ++raw_step;
    }
    last_raw_block = seconds_since(start);
    raw_seconds += last_raw_block;
    raw_steps += steps;
  }
};

struct PhysicsResult {
  int threads = 0;
  double our_steps_per_second = 0;  // summed over threads
  double raw_steps_per_second = 0;
  double cost_ratio = 0;  // median over block pairs and threads of our/raw time per step
  int warnings = 0;  // MuJoCo warnings raised in our Data and the raw Data
};

PhysicsResult measure_physics(const model::Model& model, const MocapTrajectory& trajectory,
                              int threads, double seconds) {
  std::vector<std::unique_ptr<PhysicsWorker>> workers;
  for (int t = 0; t < threads; ++t) workers.push_back(std::make_unique<PhysicsWorker>(model));
  // Block size from a short calibration of our step on one thread.
  const Clock::time_point start = Clock::now();
  long calibration = 0;
  while (seconds_since(start) < std::min(0.05, seconds / 10) || calibration < 10) {
    workers[0]->run_ours(model, 10);
    calibration += 10;
  }
  const double rate = static_cast<double>(calibration) / seconds_since(start);
  const long block = std::max(1L, static_cast<long>(rate * seconds / (2 * kRepetitions)));
  for (auto& w : workers) {
    w->our_seconds = w->raw_seconds = w->last_raw_block = 0;
    w->our_steps = w->raw_steps = 0;
    w->ratios.clear();
  }
  // Interleaved blocks, all threads in lockstep.
  std::barrier sync(threads);
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      PhysicsWorker& w = *workers[static_cast<size_t>(t)];
      for (int r = 0; r < kRepetitions; ++r) {
        sync.arrive_and_wait();
        w.run_raw(model, trajectory, block);
        sync.arrive_and_wait();
        w.run_ours(model, block);
      }
    });
  }
  for (std::thread& thread : pool) thread.join();
  PhysicsResult result;
  result.threads = threads;
  std::vector<double> ratios;
  for (auto& w : workers) {
    ratios.insert(ratios.end(), w->ratios.begin(), w->ratios.end());
    result.our_steps_per_second += static_cast<double>(w->our_steps) / w->our_seconds;
    result.raw_steps_per_second += static_cast<double>(w->raw_steps) / w->raw_seconds;
    for (int i = 0; i < mjNWARNING; ++i) {
      result.warnings += w->ours.mj->warning[i].number + w->raw->warning[i].number;
    }
  }
  result.cost_ratio = median_ratio(ratios);
  return result;
}

struct RenderResult {
  std::string camera;
  int size = 0;
  double our_fps = 0;
  double raw_fps = 0;
  double cost_ratio = 0;  // median over block pairs of our/raw time per frame
};

RenderResult measure_render(const model::Model& model, const mjData& d, render::Renderer& renderer,
                            const std::string& camera_name, double seconds) {
  const mjModel* m = model.m();
  const int camera = render::camera_id(*m, camera_name);
  render::Image image;
  std::vector<unsigned char> raw_rgb(static_cast<size_t>(renderer.width() * renderer.height() * 3));
  mjvCamera raw_camera;
  mjv_defaultCamera(&raw_camera);
  raw_camera.type = mjCAMERA_FIXED;
  raw_camera.fixedcamid = camera;
  const mjrRect viewport{0, 0, renderer.width(), renderer.height()};
  auto raw_frame = [&] {
    mjv_updateScene(m, const_cast<mjData*>(&d), &renderer.option(), nullptr, &raw_camera,
                    mjCAT_ALL, &renderer.scene());
    mjr_render(viewport, &renderer.scene(), &renderer.context());
    mjr_readPixels(raw_rgb.data(), nullptr, viewport, &renderer.context());
  };
  // Calibrate the block size on our path (this also warms up both).
  renderer.render(*m, d, camera, image);
  renderer.make_current();
  raw_frame();
  const Clock::time_point start = Clock::now();
  int calibration = 0;
  while (seconds_since(start) < std::min(0.05, seconds / 10) || calibration < 2) {
    renderer.render(*m, d, camera, image);
    ++calibration;
  }
  const double rate = calibration / seconds_since(start);
  const int block = std::max(1, static_cast<int>(rate * seconds / (2 * kRepetitions)));
  double our_seconds = 0;
  double raw_seconds = 0;
  std::vector<double> ratios;
  for (int r = 0; r < kRepetitions; ++r) {
    renderer.make_current();
    Clock::time_point t0 = Clock::now();
    for (int i = 0; i < block; ++i) raw_frame();
    const double raw = seconds_since(t0);
    t0 = Clock::now();
    for (int i = 0; i < block; ++i) renderer.render(*m, d, camera, image);
    const double ours = seconds_since(t0);
    raw_seconds += raw;
    our_seconds += ours;
    ratios.push_back(ours / raw);
  }
  RenderResult result;
  result.camera = camera_name;
  result.size = renderer.width();
  result.our_fps = kRepetitions * block / our_seconds;
  result.raw_fps = kRepetitions * block / raw_seconds;
  result.cost_ratio = median_ratio(ratios);
  return result;
}

// Frames per second of our render path with MuJoCo's default settings (for the docs' table).
double measure_default_settings(const model::Model& model, const mjData& d,
                                render::Backend backend, int size, double seconds) {
  auto renderer = render::make_renderer(backend, *model.m(), size, size,
                                        render::RenderSettings::mujoco_defaults());
  render::Image image;
  renderer->render(*model.m(), d, model.agentview_camera, image);
  const Clock::time_point start = Clock::now();
  int frames = 0;
  while (seconds_since(start) < seconds / 2 || frames < 2) {
    renderer->render(*model.m(), d, model.agentview_camera, image);
    ++frames;
  }
  return frames / seconds_since(start);
}

int run_bench(const BenchOptions& o) {
  const render::Backend backend = render::parse_backend(o.backend);
  if (!(o.seconds > 0) || o.seconds > 3600) {
    throw core::InputError("--seconds", "a duration in (0, 3600] s", fmt::format("{}", o.seconds));
  }
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const int threads = o.threads == 0 ? cores : o.threads;
  if (threads < 1 || threads > 256) {
    throw core::InputError("--threads", "1..256 (0: all cores)", std::to_string(o.threads));
  }

  // Open the JSON file first, so an unwritable path fails before minutes of measuring.
  std::ofstream json_file;
  if (!o.json.empty()) {
    json_file.open(o.json);
    if (!json_file) throw core::InputError::Message("--json", "cannot write '" + o.json + "'");
  }

  const model::Model model = model::build(model::SceneSpec::Default());
  const mjModel* m = model.m();
  const MocapTrajectory trajectory = record_mocap(model);

  // Physics on 1 thread and on all threads.
  std::vector<PhysicsResult> physics;
  physics.push_back(measure_physics(model, trajectory, 1, o.seconds));
  if (threads > 1) physics.push_back(measure_physics(model, trajectory, threads, o.seconds));

  // Render the state after one swing period of our stepping.
  sim::Data data = sim::make_data(model);
  for (int i = 0; i < trajectory.steps; ++i) {
    sim::set_human_pose(model, data, swing_pose(model, data.mj->time));
    sim::step(model, data);
  }
  std::vector<RenderResult> renders;
  std::string gl_renderer = "none";
  double default_settings_fps = 0;
  if (backend != render::Backend::kNone) {
    for (int size : {128, 224}) {
      auto renderer = render::make_renderer(backend, *m, size, size);
      gl_renderer = renderer->gl_renderer();
      for (const char* camera : {"agentview", "wrist"}) {
        renders.push_back(measure_render(model, *data.mj, *renderer, camera, o.seconds));
      }
    }
    default_settings_fps = measure_default_settings(model, *data.mj, backend, 224, o.seconds);
  }

  // Text table.
  std::printf("HRIBench %s, MuJoCo %s; default scene (ngeom %d, nbody %d), human swinging arms\n",
              std::string(core::version()).c_str(), mj_versionString(), m->ngeom, m->nbody);
  std::printf("GL_RENDERER: %s (backend %s)\n\n", gl_renderer.c_str(),
              std::string(render::to_string(backend)).c_str());
  const std::string physics_title = fmt::format("physics (dt {:g} ms)", 1000 * m->opt.timestep);
  std::printf("%-22s %14s %14s %12s %14s\n", physics_title.c_str(), "ours steps/s", "raw steps/s",
              "ours x real", "cost ours/raw");
  for (const PhysicsResult& p : physics) {
    std::printf("%-22s %14.0f %14.0f %12.1f %14.3f\n",
                (std::to_string(p.threads) + (p.threads == 1 ? " thread" : " threads")).c_str(),
                p.our_steps_per_second, p.raw_steps_per_second,
                p.our_steps_per_second * m->opt.timestep,
                p.cost_ratio);
  }
  if (!renders.empty()) {
    std::printf("\n%-22s %14s %14s %12s %14s\n", "render", "ours fps", "raw fps", "",
                "cost ours/raw");
    for (const RenderResult& r : renders) {
      std::printf("%-22s %14.1f %14.1f %12s %14.3f\n",
                  (r.camera + " " + std::to_string(r.size) + "x" + std::to_string(r.size)).c_str(),
                  r.our_fps, r.raw_fps, "", r.cost_ratio);
    }
    std::printf("(MuJoCo's default render settings: agentview 224x224 at %.1f fps)\n",
                default_settings_fps);
  }

  if (!o.json.empty()) {
    nlohmann::json j;
    j["hribench_version"] = std::string(core::version());
    j["git_hash"] = std::string(core::git_hash());
    j["mujoco_version"] = mj_versionString();
    j["backend"] = std::string(render::to_string(backend));
    j["gl_renderer"] = gl_renderer;
    j["seconds_per_measurement"] = o.seconds;
    j["timestep"] = m->opt.timestep;
    j["ngeom"] = m->ngeom;
    j["nbody"] = m->nbody;
    j["physics"] = nlohmann::json::array();
    for (const PhysicsResult& p : physics) {
      j["physics"].push_back({{"threads", p.threads},
                              {"steps_per_second", p.our_steps_per_second},
                              {"raw_steps_per_second", p.raw_steps_per_second},
                              {"realtime_factor", p.our_steps_per_second * m->opt.timestep},
                              {"raw_realtime_factor", p.raw_steps_per_second * m->opt.timestep},
                              {"cost_ratio", p.cost_ratio},
                              {"mujoco_warnings", p.warnings}});
    }
    j["render"] = nlohmann::json::array();
    for (const RenderResult& r : renders) {
      j["render"].push_back({{"camera", r.camera},
                             {"width", r.size},
                             {"height", r.size},
                             {"fps", r.our_fps},
                             {"raw_fps", r.raw_fps},
                             {"cost_ratio", r.cost_ratio}});
    }
    const render::RenderSettings settings;
    j["render_settings"] = {{"shadows", settings.shadows},
                            {"reflections", settings.reflections},
                            {"skybox", settings.skybox},
                            {"multisamples", settings.multisamples}};
    j["render_mujoco_defaults_fps_agentview_224"] = default_settings_fps;
    json_file << j.dump(2) << "\n";
    json_file.close();
    if (!json_file) throw core::InputError::Message("--json", "cannot write '" + o.json + "'");
  }
  return 0;
}

HRIB_REGISTER_COMMAND(
    "bench", "Measure physics and render speed against raw MuJoCo (like testspeed)",
    [](CLI::App& app) -> std::function<int()> {
      auto options = std::make_shared<BenchOptions>();
      app.add_option("--json", options->json, "also write the figures as JSON to this file");
      app.add_option("--seconds", options->seconds,
                     "wall seconds per measurement (ours and raw together)")
          ->capture_default_str();
      app.add_option("--threads", options->threads, "threads for the parallel row (0: all cores)")
          ->capture_default_str();
      app.add_option("--backend", options->backend, "osmesa, egl or none (no render rows)")
          ->capture_default_str();
      auto episodes = std::make_shared<EpisodeBenchOptions>();
      auto episode_mode = std::make_shared<bool>(false);
      app.add_flag("--episodes", *episode_mode,
                   "real task episodes (noop and oracle by default) against raw mj_step instead");
      app.add_option("--tasks", episodes->tasks, "--episodes: task ids or names, or all")
          ->capture_default_str();
      app.add_option("--policies", episodes->policies, "--episodes: comma-separated policies")
          ->delimiter(',')
          ->capture_default_str();
      app.add_option("--seeds", episodes->seeds, "--episodes: episodes per task (seeds from --seed)")
          ->capture_default_str();
      app.add_option("--seed", episodes->seed, "--episodes: first seed")->capture_default_str();
      app.add_option("--repeats", episodes->repeats, "--episodes: runs of each episode")
          ->capture_default_str();
      app.add_option("--horizon", episodes->horizon, "--episodes: seconds (default: the script's)");
      app.add_option("--physics", episodes->physics,
                     "--episodes: physics candidates to measure (" + std::string(kPhysicsCandidates) + "; '+' combines)")
          ->delimiter(',')
          ->capture_default_str();
      return [options, episodes, episode_mode] {
        if (!*episode_mode) return run_bench(*options);
        episodes->json = options->json;
        episodes->threads = options->threads;
        return run_episode_bench(*episodes);
      };
    });

}  // namespace
}  // namespace hribench::cli
