// `hribench eval --tasks LIST|all --policy LIST --out DIR [...]`: runs every (task, policy,
// seed) episode, scores it, appends it to DIR/episodes.jsonl as it finishes (so --resume loses
// nothing), and writes DIR/results.json, summary.md and summary.csv at the end.
// DIR/options.json records the options that change results; another run's folder is refused
// unless --resume (same options) or --force.
// With --pool DIR [--split eval|adapt|test] the episodes are those of a generated pool's split
// (gen/pool.h: re-sampled from the manifest's seeds and checked against its hashes) instead of
// sampled seeds; the results' options name the pool and its version.
// With --save-logs each episode's log is written to DIR/logs/TASK__POLICY__SEED__HASH.hlog
// (eval/episode_log.h; by an observer of the episode, atomically: temporary name + rename).
//
// Reuse: each worker thread makes one instance of each policy for the whole run and resets it
// for every episode (Policy::reset). Each episode has its own scene, hence its own MuJoCo model,
// Data and renderers (a renderer holds the model's textures and meshes); nothing is built twice
// per episode (the contract's home TCP comes from the episode's own Data).

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/command.h"
#include "core/errors.h"
#include "core/paths.h"
#include "eval/episode.h"
#include "eval/metrics.h"
#include "eval/parallel.h"
#include "eval/report.h"
#include "eval/runner.h"
#include "eval/script_contract.h"
#include "eval/script_driver.h"
#include "eval/task_episode.h"
#include "gen/pool.h"
#include "model/model.h"
#include "policy/registry.h"
#include "remote/remote.h"
#include "script/check.h"
#include "script/sample.h"
#include "sim/data.h"

namespace hribench::cli {
namespace {

namespace fs = std::filesystem;

struct EvalOptions {
  std::string tasks = "all";
  std::string policies;
  int episodes = 10;
  uint64_t seed = 0;
  int threads = 1;
  std::string latency = "none";
  double horizon = -1;  // s; -1: each script's own horizon
  std::string out;
  bool resume = false;
  bool force = false;
  std::string pool;            // a pool folder, or empty: sample seeds
  std::string split = "eval";  // with pool
  bool sampling_flags = false; // --episodes or --seed given
  bool save_logs = false;      // write DIR/logs/*.hlog
};

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

struct Job {
  const script::EpisodeSpec* spec = nullptr;
  std::string hash;
  std::string policy;
  std::string key;
};

// The policies of one worker thread: one instance per reference for the whole run.
using WorkerPolicies = std::map<std::string, std::unique_ptr<policy::Policy>>;

// The log file of an episode: DIR/logs/TASK__POLICY__SEED__HASH.hlog, with characters a file
// name should not hold in a policy reference (openpi://host:8000) replaced by '_'.
fs::path log_path(const fs::path& dir, const Job& job) {
  std::string name = job.spec->task + "__" + job.policy + "__" + std::to_string(job.spec->seed) +
                     "__" + job.hash.substr(0, 12) + ".hlog";
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') c = '_';
  }
  return dir / "logs" / name;
}

// One episode; trouble (a scene the model cannot build, any exception) -> invalid with reason.
eval::EpisodeResult run_one(const Job& job, const eval::RunOptions& base, WorkerPolicies& policies,
                            const std::optional<fs::path>& log_file) {
  const script::EpisodeSpec& spec = *job.spec;
  try {
    std::unique_ptr<policy::Policy>& policy = policies[job.policy];
    if (!policy) policy = policy::make_policy(job.policy);
    const eval::EpisodeSetup setup{spec.task, spec.role,        job.hash,
                                   spec.seed, spec.instruction, job.policy};
    std::optional<eval::LogFileWriter> writer;
    std::vector<eval::EpisodeObserver*> observers;
    if (log_file) observers.push_back(&writer.emplace(*log_file));
    const eval::ScoredEpisode scored = eval::run_task_episode(spec, *policy, setup, base, observers);
    return eval::make_result(scored.log, scored.metrics);
  } catch (const std::exception& e) {
    eval::EpisodeResult result;
    result.task = spec.task;
    result.role = spec.role;
    result.policy = job.policy;
    result.spec_hash = job.hash;
    result.seed = spec.seed;
    result.status = core::EpisodeStatus::kInvalid;
    result.status_reason = e.what();
    result.metrics.labels = {eval::FailureLabel::kInvalid};
    result.metrics.primary_label = eval::FailureLabel::kInvalid;
    return result;
  }
}

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  nlohmann::json json;
  try {
    in >> json;
  } catch (const std::exception&) {
    throw core::InputError::Message(path.string(), "not valid JSON");
  }
  return json;
}

// Refuses a folder holding another run unless --resume (same options) or --force; returns
// the episodes already finished (rewriting the episode file without a torn last line).
std::vector<eval::EpisodeResult> prepare_out(const EvalOptions& o, const nlohmann::json& options) {
  const fs::path dir = o.out;
  const fs::path options_file = dir / "options.json";
  const fs::path lines_file = dir / "episodes.jsonl";
  std::vector<eval::EpisodeResult> finished;
  const bool has_run = fs::exists(options_file) || fs::exists(lines_file) ||
                       fs::exists(dir / "results.json");
  if (has_run && o.force) {
    for (const char* name : {"options.json", "episodes.jsonl", "results.json", "summary.md",
                             "summary.csv"}) {
      fs::remove(dir / name);
    }
    fs::remove_all(dir / "logs");
  } else if (has_run && !o.resume) {
    throw core::InputError::Message(
        "--out", o.out + " already holds a run; use --resume to continue it or --force to replace it");
  } else if (has_run) {
    if (!fs::exists(options_file) || read_json(options_file) != options) {
      throw core::InputError::Message(
          "--resume", o.out + " holds a run with other options; use --force to replace it");
    }
    if (fs::exists(lines_file)) finished = eval::load_episode_lines(lines_file);
    fs::remove(lines_file);
    for (const eval::EpisodeResult& r : finished) eval::append_episode_line(lines_file, r);
  }
  fs::create_directories(dir);
  std::ofstream(options_file) << options.dump(2) << "\n";
  return finished;
}

int run_eval(const EvalOptions& o) {
  // Contradictory or bad options first: one line, exit 2.
  if (o.resume && o.force) {
    throw core::InputError::Message("--resume", "cannot be combined with --force");
  }
  if (o.episodes <= 0) {
    throw core::InputError("--episodes", "a positive number", std::to_string(o.episodes));
  }
  if (o.threads <= 0) {
    throw core::InputError("--threads", "a positive number", std::to_string(o.threads));
  }
  if (o.horizon != -1 && !(o.horizon > 0)) {
    throw core::InputError("--horizon", "a positive number of seconds", std::to_string(o.horizon));
  }
  const eval::Latency latency = eval::parse_latency(o.latency);
  const std::vector<std::string> policies = split_list(o.policies);
  if (policies.empty()) throw core::InputError("--policy", "a policy list", "'" + o.policies + "'");
  for (const std::string& p : policies) policy::make_policy(p);  // unknown -> InputError

  // The episodes, grouped by task: sampled seeds, or a pool's split.
  std::vector<std::vector<script::EpisodeSpec>> by_task;
  nlohmann::json options;
  if (!o.pool.empty()) {
    if (o.sampling_flags) {
      throw core::InputError::Message("--pool", "takes its episodes from the pool; drop --episodes and --seed");
    }
    const gen::Split split = gen::split_from_name(o.split, "--split");
    const gen::Manifest manifest = gen::read_manifest(o.pool);
    const std::vector<std::string> names = o.tasks == "all" ? std::vector<std::string>{} : split_list(o.tasks);
    std::vector<script::EpisodeSpec> specs = gen::pool_episodes(manifest, split, names);
    if (specs.empty()) {
      throw core::InputError("--tasks", "tasks of the pool", "'" + o.tasks + "' (no episodes in split " + o.split + ")");
    }
    std::vector<std::string> tasks;
    for (script::EpisodeSpec& spec : specs) {
      if (tasks.empty() || tasks.back() != spec.task) {
        tasks.push_back(spec.task);
        by_task.emplace_back();
      }
      by_task.back().push_back(std::move(spec));
    }
    options = {{"tasks", tasks},
               {"policies", policies},
               {"pool", o.pool},
               {"pool_version", manifest.pool_version},
               {"split", o.split},
               {"latency", eval::to_string(latency)},
               {"horizon", o.horizon > 0 ? nlohmann::json(o.horizon) : nlohmann::json("script")}};
  } else {
    if (o.split != "eval") throw core::InputError::Message("--split", "needs --pool (a pool's split)");
    const std::vector<std::string> task_files = gen::resolve_task_scripts(o.tasks);
    for (const std::string& file : task_files) {
      const script::Scenario scenario = script::load_scenario(core::resolve_data_path(file).string());
      by_task.emplace_back();
      for (int i = 0; i < o.episodes; ++i) {
        by_task.back().push_back(script::sample(scenario, o.seed + static_cast<uint64_t>(i)));
      }
    }
    options = {{"tasks", task_files},    {"policies", policies},
               {"episodes", o.episodes}, {"seed", o.seed},
               {"latency", eval::to_string(latency)},
               {"horizon", o.horizon > 0 ? nlohmann::json(o.horizon) : nlohmann::json("script")}};
  }
  const std::vector<eval::EpisodeResult> finished = prepare_out(o, options);
  std::map<std::string, eval::EpisodeResult> by_key;
  for (const eval::EpisodeResult& r : finished) by_key.emplace(eval::episode_key(r), r);

  // Jobs in (task, policy, episode) order; those already finished are skipped.
  std::vector<Job> all_jobs;
  std::vector<size_t> todo;
  for (const std::vector<script::EpisodeSpec>& specs : by_task) {
    for (const std::string& p : policies) {
      for (const script::EpisodeSpec& spec : specs) {
        Job job;
        job.spec = &spec;
        job.hash = script::spec_hash(spec);
        job.policy = p;
        job.key = eval::episode_key(spec.task, p, job.hash, spec.seed);
        if (by_key.count(job.key) == 0) todo.push_back(all_jobs.size());
        all_jobs.push_back(std::move(job));
      }
    }
  }

  eval::RunOptions run_options;
  run_options.latency = latency;
  run_options.horizon = o.horizon > 0 ? o.horizon : 0;  // 0: each script's own horizon

  // Run, appending each episode as it finishes, with a one-line progress indicator.
  const fs::path lines_file = fs::path(o.out) / "episodes.jsonl";
  if (o.save_logs) fs::create_directories(fs::path(o.out) / "logs");
  std::vector<WorkerPolicies> worker_policies(static_cast<size_t>(o.threads));
  const auto start = std::chrono::steady_clock::now();
  size_t done = 0;
  // A remote policy that cannot connect for remote::kMaxConnectFailures episodes in a row stops
  // the run (docs/remote-policies.md). Those episodes are held back, not written, so --resume
  // runs them again; an isolated connection failure is written once a later episode connects.
  std::vector<eval::EpisodeResult> unconnected;
  std::atomic<bool> stop{false};
  const auto append = [&](const eval::EpisodeResult& result) {
    eval::append_episode_line(lines_file, result);
    ++done;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0;
    const double eta = rate > 0 ? static_cast<double>(todo.size() - done) / rate : 0;
    std::fprintf(stderr, "\rhribench eval: %zu/%zu episodes (%zu resumed), %.2f ep/s, ETA %.0f s ",
                 done + finished.size(), all_jobs.size(), finished.size(), rate, eta);
    std::fflush(stderr);
  };
  std::vector<eval::EpisodeResult> results;
  try {
    results = eval::run_jobs(
        todo.size(), o.threads,
        [&](size_t job, int worker) {
          if (stop) throw std::runtime_error("stopped");
          const Job& j = all_jobs[todo[job]];
          const std::optional<fs::path> log_file =
              o.save_logs ? std::optional<fs::path>(log_path(o.out, j)) : std::nullopt;
          return run_one(j, run_options, worker_policies[static_cast<size_t>(worker)], log_file);
        },
        [&](size_t, const eval::EpisodeResult& result) {
          if (remote::is_connect_failure(result.status_reason)) {
            unconnected.push_back(result);
            if (static_cast<int>(unconnected.size()) >= remote::kMaxConnectFailures) stop = true;
            return;
          }
          for (const eval::EpisodeResult& held : unconnected) append(held);
          unconnected.clear();
          append(result);
        });
  } catch (const std::exception&) {
    if (!stop) throw;
  }
  if (stop) {
    std::fprintf(stderr, "\nhribench eval: stopped: %d episodes in a row could not connect (%s); %zu episodes are in %s, "
                 "continue with --resume\n", remote::kMaxConnectFailures, unconnected.back().status_reason.c_str(),
                 done + finished.size(), lines_file.string().c_str());
    return 1;
  }
  for (const eval::EpisodeResult& held : unconnected) append(held);
  if (!todo.empty()) std::fprintf(stderr, "\n");
  for (size_t i = 0; i < todo.size(); ++i) by_key.insert_or_assign(all_jobs[todo[i]].key, results[i]);

  // Results in job order whatever the completion order or resume history.
  eval::RunResults run;
  run.info = eval::current_run_info("none", options, run_options.constants);
  for (const Job& job : all_jobs) run.episodes.push_back(by_key.at(job.key));
  eval::write_run(o.out, run);
  std::fputs(eval::summary_markdown(run).c_str(), stdout);
  return 0;
}

HRIB_REGISTER_COMMAND(
    "eval", "Run policies on tasks and score the episodes",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<EvalOptions>();
      app.add_option("--tasks", o->tasks, "Task names, files, or all (comma-separated; default all)");
      app.add_option("--policy", o->policies, "Policy references (comma-separated)")->required();
      CLI::Option* episodes =
          app.add_option("--episodes", o->episodes, "Episodes per task and policy (seeds S..S+N-1)");
      CLI::Option* seed = app.add_option("--seed", o->seed, "First seed");
      app.add_option("--pool", o->pool, "Evaluate the episodes of this generated pool (hribench generate)");
      app.add_option("--split", o->split, "The pool's split: eval (default), adapt or test");
      app.add_option("--threads", o->threads, "Worker threads");
      app.add_option("--latency", o->latency, "none | fixed:MS | measured");
      app.add_option("--horizon", o->horizon, "Episode length in seconds (default: the script's)");
      app.add_option("--out", o->out, "Output folder")->required();
      app.add_flag("--resume", o->resume, "Continue the run in --out (same options)");
      app.add_flag("--force", o->force, "Replace the run in --out");
      app.add_flag("--save-logs", o->save_logs,
                   "Write each episode's log to DIR/logs/*.hlog (hribench's binary episode log)");
      return [o, episodes, seed] {
        o->sampling_flags = episodes->count() > 0 || seed->count() > 0;
        return run_eval(*o);
      };
    });

}  // namespace
}  // namespace hribench::cli
