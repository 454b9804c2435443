#include "cli/episode_bench.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <malloc.h>
#include <mujoco/mujoco.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/paths.h"
#include "core/version.h"
#include "eval/episode.h"
#include "eval/episode_log.h"
#include "eval/metrics.h"
#include "eval/raw_replay.h"
#include "eval/runner.h"
#include "eval/script_driver.h"
#include "gen/pool.h"
#include "model/model.h"
#include "policy/registry.h"
#include "script/check.h"
#include "script/sample.h"
#include "sim/data.h"

namespace hribench::cli {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// ---- Memory (Linux /proc): the process's resident set and its peak, in KiB. ----

long status_kib(const char* key) {
  std::ifstream status("/proc/self/status");
  std::string line;
  const size_t n = std::strlen(key);
  while (std::getline(status, line)) {
    if (line.compare(0, n, key) == 0) return std::atol(line.c_str() + n);
  }
  return 0;
}
long rss_kib() { return status_kib("VmRSS:"); }
long peak_rss_kib() { return status_kib("VmHWM:"); }
// Returns the heap's free memory to the system (so that the resident set counts what is in
// use), then resets the peak (VmHWM) to the current resident set; false where the kernel
// refuses the reset.
bool reset_peak_rss() {
  malloc_trim(0);
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

// ---- Physics candidates (measured only; the benchmark's physics is the scene as built). ----

// The parts of candidate `name` (see the header), joined by '+'.
std::vector<std::string> candidate_parts(const std::string& name) {
  std::vector<std::string> parts;
  for (size_t from = 0; from < name.size();) {
    const size_t plus = std::min(name.find('+', from), name.size());
    parts.push_back(name.substr(from, plus - from));
    from = plus + 1;
  }
  return parts;
}

// Applies the parts of a candidate that change the scene before it is built (no-base-feet), how
// the episode observes (observe-forward) or poses the person (person-per-physics-step); returns
// the others, for apply_physics.
std::vector<std::string> apply_scene_parts(const std::string& name, model::SceneSpec& scene,
                                           eval::RunOptions& options) {
  std::vector<std::string> rest;
  for (const std::string& part : candidate_parts(name)) {
    if (part == "no-base-feet") {
      scene.base_feet = false;
    } else if (part == "observe-forward") {
      options.forward_after_control_step = true;
    } else if (part == "person-per-physics-step") {
      options.person_pose_per_physics_step = true;
    } else {
      rest.push_back(part);
    }
  }
  return rest;
}

// Applies candidate parts that change a built model's mjModel.
void apply_physics(const std::vector<std::string>& parts, model::Model& model) {
  mjModel* m = model.mj.get();
  for (const std::string& part : parts) {
    const size_t eq = part.find('=');
    const std::string key = part.substr(0, eq);
    const std::string value = eq == std::string::npos ? "" : part.substr(eq + 1);
    char* end = nullptr;
    const double number = std::strtod(value.c_str(), &end);
    const bool numeric = !value.empty() && end == value.c_str() + value.size() && number > 0;
    if (part == "as-built") {
    } else if (part == "implicit") {
      m->opt.integrator = mjINT_IMPLICIT;
      model::servo_damping_in_servos(model);
    } else if (part == "euler") {
      m->opt.integrator = mjINT_EULER;
      model::servo_damping_in_servos(model);
      for (const int a : model.arm_actuator) {
        const int joint = m->actuator_trnid[2 * a];
        m->dof_damping[m->jnt_dofadr[joint]] += model::servo_kv(*m, a);
        m->actuator_biasprm[a * mjNBIAS + 2] = 0;
      }
    } else if (part == "euler-servo") {
      m->opt.integrator = mjINT_EULER;
      model::servo_damping_in_servos(model);
      model::servo_damping_in_joints(model);
    } else if (key == "timestep" && numeric) {
      m->opt.timestep = number;
    } else if (key == "iterations" && numeric && number == std::floor(number) && number <= 1000) {
      m->opt.iterations = static_cast<int>(number);
    } else if (key == "tolerance" && numeric) {
      m->opt.tolerance = number;
    } else if (key == "impratio" && numeric) {
      m->opt.impratio = number;
    } else if (key == "noslip" && numeric && number == std::floor(number) && number <= 1000) {
      m->opt.noslip_iterations = static_cast<int>(number);
    } else if ((key == "grasp-timeconst" || key == "grasp-dmax") && numeric) {
      // The contacts of a grasp: every geom of the fingers (pads included) and of the objects.
      // MuJoCo mixes two geoms' solref and solimp (solmix), so a pad against an object gets
      // these values (up to rounding).
      if (key == "grasp-dmax" && number >= 1) {
        throw core::InputError("--physics", "grasp-dmax below 1", "'" + part + "'");
      }
      for (int g = 0; g < m->ngeom; ++g) {
        const model::GeomOwner owner = model.geom_tags[g].owner;
        if (owner != model::GeomOwner::kRobotFinger && owner != model::GeomOwner::kObject) continue;
        if (key == "grasp-timeconst") {
          m->geom_solref[mjNREF * g] = number;
        } else {
          m->geom_solimp[mjNIMP * g + 1] = number;
        }
      }
    } else if (key == "finger-armature" && numeric) {
      for (const int dof : model.finger_dof_adr) m->dof_armature[dof] = number;
      // The constants MuJoCo derives from the inertia at compile time (dof_invweight0, which
      // scales the contacts' regularisation) follow the new armature.
      std::unique_ptr<mjData, sim::MjDataDeleter> scratch(mj_makeData(m));
      mj_setConst(m, scratch.get());
    } else {
      throw core::InputError("--physics", std::string(kPhysicsCandidates) + ", joined by '+'",
                             "'" + part + "'");
    }
  }
}

// ---- One measured episode. ----

struct EpisodeFigures {
  double setup_seconds = 0;  // model build + Episode (Data, driver, contract, renderers)
  double seconds = 0;        // setup + run + metrics: what `hribench eval` spends on it
  double raw_seconds = 0;    // raw mj_step for the same physics steps on the same model
  long control_steps = 0;
  long physics_steps = 0;
  long peak_kib = 0;         // peak resident memory the episode added (0: unknown)
  int maxuse_con = 0, maxuse_efc = 0, maxuse_stack = 0;
  int nconmax = 0, njmax = 0, nstack = 0;
  std::string status;
  bool success = false;
  std::string label;     // primary failure label
  double max_human_force = 0;     // N, the episode's peak contact force on the person
  bool critical_contact = false;  // a contact on the person above its ISO/TS 15066 limit
  bool differs = false;  // outcome or log differs from the first physics candidate's
};

struct Runner {
  std::map<std::string, std::unique_ptr<policy::Policy>> policies;  // one per reference
  policy::Policy& policy(const std::string& ref) {
    std::unique_ptr<policy::Policy>& p = policies[ref];
    if (!p) p = policy::make_policy(ref);
    return *p;
  }
};

// Runs one episode as `hribench eval` does; returns its figures and (when asked) its model
// and log for the raw replay.
EpisodeFigures run_one(const script::EpisodeSpec& spec, const std::string& ref, Runner& runner,
                       const eval::RunOptions& options, const std::string& physics, bool measure_memory,
                       std::shared_ptr<const model::Model>* model_out = nullptr,
                       eval::EpisodeLog* log_out = nullptr, eval::EpisodeObserver* observer = nullptr) {
  policy::Policy& policy = runner.policy(ref);
  EpisodeFigures f;
  const bool peak_known = measure_memory && reset_peak_rss();
  const long rss_before = measure_memory ? rss_kib() : 0;
  const Clock::time_point start = Clock::now();
  model::SceneSpec scene = eval::scene_spec_from_episode(spec);
  eval::RunOptions run = options;
  const std::vector<std::string> model_parts = apply_scene_parts(physics, scene, run);
  model::Model built = model::build(scene);
  apply_physics(model_parts, built);
  auto model = std::make_shared<const model::Model>(std::move(built));
  eval::Episode episode(spec, policy.spec(), eval::setup_of(spec, ref), run, model);
  if (observer) episode.add_observer(*observer);
  f.setup_seconds = seconds_since(start);
  const eval::EpisodeLog& log = eval::run_episode(episode, policy);
  const eval::EpisodeMetrics metrics = episode.metrics();
  f.seconds = seconds_since(start);
  if (peak_known) f.peak_kib = std::max(0L, peak_rss_kib() - rss_before);
  f.control_steps = static_cast<long>(log.steps.size()) - 1;
  const mjData& d = *episode.data().mj;
  const mjModel& m = *model->m();
  f.physics_steps = f.control_steps * std::lround(options.control_dt / m.opt.timestep);
  f.maxuse_con = d.maxuse_con;
  f.maxuse_efc = d.maxuse_efc;
  f.maxuse_stack = d.maxuse_stack;
  f.nconmax = m.nconmax;
  f.njmax = m.njmax;
  f.nstack = m.nstack;
  f.status = std::string(core::to_string(log.status));
  f.success = metrics.success;
  f.label = metrics.primary_label ? std::string(eval::to_string(*metrics.primary_label)) : "";
  f.max_human_force = metrics.max_human_force;
  f.critical_contact = metrics.critical_contact;
  if (model_out) *model_out = model;
  if (log_out) *log_out = log;
  return f;
}

struct TaskRow {
  std::string task;
  std::string policy;
  std::string physics;
  std::vector<EpisodeFigures> episodes;
};

struct ScalingRow {
  int threads = 0;
  int episodes = 0;
  double seconds = 0;
  long peak_kib_per_worker = 0;
};

ScalingRow run_scaling(const std::vector<script::EpisodeSpec>& specs,
                       const std::vector<std::string>& refs, const eval::RunOptions& options,
                       int threads) {
  struct Job {
    const script::EpisodeSpec* spec;
    const std::string* ref;
  };
  std::vector<Job> jobs;
  for (const script::EpisodeSpec& spec : specs) {
    for (const std::string& ref : refs) jobs.push_back({&spec, &ref});
  }
  std::vector<Runner> runners(static_cast<size_t>(threads));
  for (Runner& r : runners) {
    for (const std::string& ref : refs) r.policy(ref);
  }
  std::atomic<size_t> next{0};
  std::mutex error_mutex;
  std::string error;
  const bool peak_known = reset_peak_rss();
  const long rss_before = rss_kib();
  const Clock::time_point start = Clock::now();
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      for (size_t j = next++; j < jobs.size(); j = next++) {
        try {
          run_one(*jobs[j].spec, *jobs[j].ref, runners[static_cast<size_t>(t)], options, "as-built", false);
        } catch (const std::exception& e) {
          std::lock_guard lock(error_mutex);
          if (error.empty()) error = e.what();
        }
      }
    });
  }
  for (std::thread& thread : pool) thread.join();
  if (!error.empty()) throw core::InputError::Message("bench --episodes", error);
  ScalingRow row;
  row.threads = threads;
  row.episodes = static_cast<int>(jobs.size());
  row.seconds = seconds_since(start);
  if (peak_known) row.peak_kib_per_worker = std::max(0L, peak_rss_kib() - rss_before) / threads;
  return row;
}

}  // namespace

int run_episode_bench(const EpisodeBenchOptions& o) {
  if (o.seeds < 1) throw core::InputError("--seeds", "a positive number of episodes per task", std::to_string(o.seeds));
  if (o.repeats < 1) throw core::InputError("--repeats", "a positive number of runs per episode", std::to_string(o.repeats));
  if (o.horizon != -1 && !(o.horizon > 0)) {
    throw core::InputError("--horizon", "a positive number of seconds", fmt::format("{}", o.horizon));
  }
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const int threads = o.threads == 0 ? cores : o.threads;
  if (threads < 1 || threads > 256) {
    throw core::InputError("--threads", "1..256 (0: all cores)", std::to_string(o.threads));
  }
  const std::vector<std::string>& refs = o.policies;
  if (refs.empty()) throw core::InputError("--policies", "a policy list", "none");
  for (const std::string& ref : refs) policy::make_policy(ref);  // unknown -> InputError
  std::ofstream json_file;
  if (!o.json.empty()) {
    json_file.open(o.json);
    if (!json_file) throw core::InputError::Message("--json", "cannot write '" + o.json + "'");
  }

  std::vector<script::EpisodeSpec> specs;
  for (const std::string& file : gen::resolve_task_scripts(o.tasks)) {
    const script::Scenario scenario = script::load_scenario(core::resolve_data_path(file).string());
    for (int i = 0; i < o.seeds; ++i) specs.push_back(script::sample(scenario, o.seed + static_cast<uint64_t>(i)));
  }
  eval::RunOptions options;
  options.horizon = o.horizon;

  // Per task, policy and physics: one recording run, then the timed runs with raw MuJoCo
  // alongside (one worker, this thread).
  if (o.physics.empty()) throw core::InputError("--physics", "a list of physics candidates", "none");
  std::vector<TaskRow> rows;
  std::map<std::tuple<std::string, std::string, std::string>, size_t> row_of;  // -> rows
  Runner runner;
  for (const std::string& ref : refs) runner.policy(ref);
  for (const script::EpisodeSpec& spec : specs) {
    for (const std::string& ref : refs) {
      std::vector<eval::EpisodeLog> first_logs;  // of the first candidate, per repeat
      std::vector<EpisodeFigures> first_figures;
      for (const std::string& physics : o.physics) {
        const auto key = std::make_tuple(spec.task, ref, physics);
        if (row_of.count(key) == 0) {
          row_of[key] = rows.size();
          rows.push_back({spec.task, ref, physics, {}});
        }
        TaskRow& row = rows[row_of[key]];
        // What raw MuJoCo replays comes from one more run of the episode, not timed: an episode
        // is deterministic, so the timed runs' logs are its log (checked).
        const std::string what = fmt::format("{} seed {} with {} ({})", spec.task, spec.seed, ref, physics);
        const auto check_raw = [&what](long differs) {
          if (differs < 0) return;
          throw core::InputError::Message(
              "bench --episodes", fmt::format("raw mj_step did not make physics step {} of {} as the episode did", differs, what));
        };
        eval::RawRecording recording;
        eval::EpisodeLog recorded;
        std::shared_ptr<const model::Model> model;
        run_one(spec, ref, runner, options, physics, false, &model, &recorded, &recording);
        // Raw's data, made and used once before the timed runs (its memory is not theirs).
        const sim::MjDataPtr raw(mj_makeData(model->m()));
        check_raw(recording.replay(model->m(), raw.get(), 0, recording.steps()));
        for (int r = 0; r < o.repeats; ++r) {
          eval::EpisodeLog log;
          eval::RawAlongside alongside(recording, raw.get());
          EpisodeFigures f = run_one(spec, ref, runner, options, physics, true, nullptr, &log, &alongside);
          if (!eval::identical(log, recorded)) {
            throw core::InputError::Message("bench --episodes", what + " ran differently twice");
          }
          check_raw(alongside.differs());
          f.raw_seconds = alongside.seconds();
          f.seconds -= f.raw_seconds;
          const size_t k = static_cast<size_t>(r);
          if (physics == o.physics.front()) {
            first_logs.push_back(std::move(log));
            first_figures.push_back(f);
          } else {
            const EpisodeFigures& a = first_figures.at(k);
            f.differs = a.success != f.success || a.status != f.status || a.label != f.label ||
                        !eval::identical(first_logs.at(k), log);
          }
          row.episodes.push_back(f);
        }
      }
    }
  }
  std::vector<ScalingRow> scaling;
  if (threads > 1) {
    scaling.push_back(run_scaling(specs, refs, options, 1));
    scaling.push_back(run_scaling(specs, refs, options, threads));
  }

  // Text table.
  std::printf("HRIBench %s, MuJoCo %s; real task episodes (%d seed%s x %d repeat%s), one worker\n",
              std::string(core::version()).c_str(), mj_versionString(), o.seeds, o.seeds == 1 ? "" : "s",
              o.repeats, o.repeats == 1 ? "" : "s");
  int physics_width = 14;  // the column fits the longest candidate
  for (const std::string& p : o.physics) physics_width = std::max(physics_width, static_cast<int>(p.size()));
  std::printf("%-22s %-24s %-*s %9s %9s %10s %11s %11s %8s %8s %9s %11s %11s %5s %6s %8s %5s\n", "task", "policy", physics_width, "physics", "s/episode",
              "setup s", "control/s", "physics/s", "raw phys/s", "cost/raw", "run/raw", "peak MB",
              "efc/njmax", "con/nconmax", "succ", "differ", "human N", "crit");
  nlohmann::json json_rows = nlohmann::json::array();
  for (const TaskRow& row : rows) {
    double seconds = 0, setup = 0, raw = 0;
    long control = 0, physics = 0, peak = 0;
    int efc = 0, con = 0, stack = 0;
    std::vector<double> ratios, run_ratios;
    int successes = 0, differ = 0, critical = 0;
    double human_force = 0;
    for (const EpisodeFigures& f : row.episodes) {
      seconds += f.seconds;
      setup += f.setup_seconds;
      raw += f.raw_seconds;
      control += f.control_steps;
      physics += f.physics_steps;
      peak = std::max(peak, f.peak_kib);
      efc = std::max(efc, f.maxuse_efc);
      con = std::max(con, f.maxuse_con);
      stack = std::max(stack, f.maxuse_stack);
      ratios.push_back(f.seconds / f.raw_seconds);
      run_ratios.push_back((f.seconds - f.setup_seconds) / f.raw_seconds);
      successes += f.success ? 1 : 0;
      differ += f.differs ? 1 : 0;
      critical += f.critical_contact ? 1 : 0;
      human_force = std::max(human_force, f.max_human_force);
    }
    const double n = static_cast<double>(row.episodes.size());
    const EpisodeFigures& first = row.episodes.front();
    std::printf("%-22s %-24s %-*s %9.3f %9.3f %10.0f %11.0f %11.0f %8.3f %8.3f %9.1f %5d/%-5d %5d/%-5d %5d %6d %8.0f %5d\n",
                row.task.c_str(), row.policy.c_str(), physics_width, row.physics.c_str(), seconds / n, setup / n, control / seconds,
                physics / seconds, physics / raw, median(ratios), median(run_ratios), peak / 1024.0,
                efc, first.njmax, con, first.nconmax, successes, differ, human_force, critical);
    json_rows.push_back({{"task", row.task},
                         {"policy", row.policy},
                         {"episodes", row.episodes.size()},
                         {"physics", row.physics},
                         {"successes", successes},
                         {"differ_from_first_physics", differ},
                         {"max_human_force", human_force},
                         {"critical_contacts", critical},
                         {"seconds_per_episode", seconds / n},
                         {"setup_seconds_per_episode", setup / n},
                         {"control_steps_per_second", control / seconds},
                         {"physics_steps_per_second", physics / seconds},
                         {"raw_physics_steps_per_second", physics / raw},
                         {"physics_steps_per_episode", static_cast<double>(physics) / n},
                         {"cost_ratio", median(ratios)},
                         {"run_cost_ratio", median(run_ratios)},
                         {"peak_mib_per_worker", peak / 1024.0},
                         {"maxuse_efc", efc},
                         {"njmax", first.njmax},
                         {"maxuse_con", con},
                         {"nconmax", first.nconmax},
                         {"maxuse_stack", stack},
                         {"nstack", first.nstack}});
  }
  std::printf("(differ: episodes whose outcome or log differs from the first --physics candidate's; "
              "cost/raw: episode wall time / raw mj_step making the same steps on the same model, "
              "alongside, median over episodes; run/raw: the same without the setup; peak MB: resident memory one episode adds; "
              "human N: the largest contact force on the person in the row's episodes; crit: episodes with a "
              "critical contact)\n");
  for (const ScalingRow& s : scaling) {
    std::printf("%d thread%s: %d episodes in %.2f s, %.3f episodes/s, peak %.1f MB per worker\n", s.threads,
                s.threads == 1 ? "" : "s", s.episodes, s.seconds, s.episodes / s.seconds,
                s.peak_kib_per_worker / 1024.0);
  }
  std::printf("process peak resident memory: %.1f MB\n", status_kib("VmHWM:") / 1024.0);

  if (!o.json.empty()) {
    nlohmann::json j;
    j["hribench_version"] = std::string(core::version());
    j["git_hash"] = std::string(core::git_hash());
    j["mujoco_version"] = mj_versionString();
    j["seeds"] = o.seeds;
    j["seed"] = o.seed;
    j["repeats"] = o.repeats;
    j["horizon"] = o.horizon > 0 ? nlohmann::json(o.horizon) : nlohmann::json("script");
    j["tasks"] = json_rows;
    j["scaling"] = nlohmann::json::array();
    for (const ScalingRow& s : scaling) {
      j["scaling"].push_back({{"threads", s.threads},
                              {"episodes", s.episodes},
                              {"seconds", s.seconds},
                              {"episodes_per_second", s.episodes / s.seconds},
                              {"peak_mib_per_worker", s.peak_kib_per_worker / 1024.0}});
    }
    json_file << j.dump(2) << "\n";
    json_file.close();
    if (!json_file) throw core::InputError::Message("--json", "cannot write '" + o.json + "'");
  }
  return 0;
}

}  // namespace hribench::cli
