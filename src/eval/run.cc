#include "eval/run.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <exception>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <utility>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "core/json.h"
#include "core/log.h"
#include "eval/episode_files.h"
#include "eval/metrics.h"
#include "eval/parallel.h"
#include "eval/ranks.h"
#include "eval/task_episode.h"
#include "script/sample.h"

namespace hribench::eval {
namespace {

namespace fs = std::filesystem;

struct Job {
  const script::EpisodeSpec* spec = nullptr;
  std::string task_id;  // docs/tasks.md's id of the task ("" for a script outside tasks/)
  std::string hash;
  std::string policy;
  std::string key;
};

// What one worker thread keeps for the whole run: one instance of each policy, and the scene
// of the spec it ran last (model, Data, renderers: the next policy's episode of that spec
// builds nothing).
struct Worker {
  std::map<std::string, std::unique_ptr<policy::Policy>> policies;
  std::unique_ptr<EpisodeScene> scene;
};

// The log file of an episode: DIR/logs/STEM.hlog (eval/episode_files.h).
fs::path log_path(const fs::path& dir, const Job& job) {
  return log_file(dir, episode_stem(job.spec->task, job.policy, job.spec->seed, job.hash));
}

// One episode; trouble (a scene the model cannot build, any exception) -> invalid with reason.
EpisodeResult run_one(const Job& job, const RunSettings& settings, Worker& worker, const PolicyMaker& make) {
  const std::optional<fs::path> log_file =
      settings.save_logs ? std::optional<fs::path>(log_path(settings.out, job)) : std::nullopt;
  const script::EpisodeSpec& spec = *job.spec;
  EpisodeResult result;
  try {
    std::unique_ptr<policy::Policy>& policy = worker.policies[job.policy];
    if (!policy) policy = make(job.policy);
    if (!worker.scene || script::spec_hash(worker.scene->spec()) != job.hash) {
      worker.scene.reset();  // one scene in memory per worker
      worker.scene = std::make_unique<EpisodeScene>(spec);
    }
    const EpisodeSetup setup{spec.task, spec.role, job.hash, spec.seed, spec.instruction, job.policy};
    std::optional<LogFileWriter> writer;
    std::vector<EpisodeObserver*> observers;
    if (log_file) observers.push_back(&writer.emplace(*log_file));
    const ScoredEpisode scored = run_task_episode(*worker.scene, *policy, setup, settings.run_options, observers);
    result = make_result(scored.log, scored.metrics);
    if (settings.after_episode) {
      try {
        settings.after_episode(spec, scored.log, result,
                               episode_stem(spec.task, job.policy, spec.seed, job.hash));
      } catch (const std::exception& e) {
        spdlog::warn("{}: {}", episode_stem(spec.task, job.policy, spec.seed, job.hash), e.what());
      }
    }
  } catch (const std::exception& e) {
    result = EpisodeResult{};
    result.task = spec.task;
    result.role = spec.role;
    result.policy = job.policy;
    result.spec_hash = job.hash;
    result.seed = spec.seed;
    result.status = core::EpisodeStatus::kInvalid;
    result.status_reason = e.what();
    result.metrics.labels = {FailureLabel::kInvalid};
    result.metrics.primary_label = FailureLabel::kInvalid;
  }
  // What the spec knows and the log does not, for both ends.
  result.task_id = job.task_id;
  result.variant = spec.variant;
  return result;
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

// The options of `recorded` that `asked` sets otherwise: "episodes: 2 in the run, 3 asked".
std::vector<std::string> option_differences(const nlohmann::json& recorded, const nlohmann::json& asked) {
  std::vector<std::string> differences;
  std::set<std::string> keys;
  for (const auto& [key, value] : recorded.items()) keys.insert(key);
  for (const auto& [key, value] : asked.items()) keys.insert(key);
  for (const std::string& key : keys) {
    const std::string was = recorded.contains(key) ? recorded.at(key).dump() : "(not set)";
    const std::string now = asked.contains(key) ? asked.at(key).dump() : "(not set)";
    if (was != now) differences.push_back(key + ": " + was + " in the run, " + now + " asked");
  }
  return differences;
}

// A run with the same options but more --episodes (the same first seed): the asked run extends
// the recorded one with the next seeds.
bool extends(const nlohmann::json& recorded, const nlohmann::json& asked) {
  if (!recorded.contains("episodes") || !asked.contains("episodes")) return false;
  nlohmann::json recorded_rest = recorded;
  nlohmann::json asked_rest = asked;
  recorded_rest.erase("episodes");
  asked_rest.erase("episodes");
  return recorded_rest == asked_rest && recorded.at("episodes").is_number_integer() &&
         asked.at("episodes").get<int>() >= recorded.at("episodes").get<int>();
}

// Refuses a file, an episode pool, or a folder holding another run unless resume (same
// options, or more episodes) or force; returns the episodes already finished (rewriting the
// episode file without a torn last line).
std::vector<EpisodeResult> prepare_out(const RunSettings& s, const nlohmann::json& options) {
  const fs::path& dir = s.out;
  const std::string out = dir.string();
  const fs::path options_file = dir / "options.json";
  const fs::path lines_file = dir / "episodes.jsonl";
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    throw core::InputError("--out", "a folder for the run", "'" + out + "', a file");
  }
  if (fs::exists(dir / "manifest.json", ec)) {
    throw core::InputError("--out", "a folder for the run",
                           "'" + out + "', which holds an episode pool (manifest.json); choose another folder");
  }
  std::vector<EpisodeResult> finished;
  const bool has_run = fs::exists(options_file) || fs::exists(lines_file) ||
                       fs::exists(dir / "results.json");
  if (has_run && s.force) {
    for (const char* name : {"options.json", "episodes.jsonl", "results.json", "summary.md",
                             "summary.csv", "report.html"}) {
      fs::remove(dir / name);
    }
    for (const char* folder : {"logs", "videos", "replay"}) fs::remove_all(dir / folder);
  } else if (has_run && !s.resume) {
    throw core::InputError::Message(
        "--out", out + " already holds a run; use --resume to continue it or --force to replace it");
  } else if (has_run) {
    if (!fs::exists(options_file)) {
      throw core::InputError::Message("--resume", out + " holds no options.json; use --force to replace the run");
    }
    const nlohmann::json recorded = read_json(options_file);
    if (recorded != options && !extends(recorded, options)) {
      std::string list;
      for (const std::string& d : option_differences(recorded, options)) list += (list.empty() ? "" : "; ") + d;
      throw core::InputError::Message(
          "--resume", out + " holds a run with other options (" + list + "); use --force to replace it");
    }
    if (fs::exists(lines_file)) finished = load_episode_lines(lines_file);
    fs::remove(lines_file);
    for (const EpisodeResult& r : finished) append_episode_line(lines_file, r);
  }
  fs::create_directories(dir);
  core::write_file_atomically(options_file, options.dump(2) + "\n");
  return finished;
}

// Every job of the plan in (task, policy, episode) order (a shard's: every N-th), with the order
// in which they are handed out: episode by episode, the policies of an episode one after
// another (each worker keeps the scene it ran last).
struct JobList {
  std::vector<Job> jobs;
  std::vector<std::array<size_t, 3>> hand_out;  // per job: (task, episode, policy)
};

JobList plan_jobs(const RunPlan& plan) {
  JobList list;
  size_t job_number = 0;
  for (size_t task = 0; task < plan.by_task.size(); ++task) {
    const std::vector<script::EpisodeSpec>& specs = plan.by_task[task];
    for (size_t policy_index = 0; policy_index < plan.policies.size(); ++policy_index) {
      const std::string& p = plan.policies[policy_index];
      for (size_t episode = 0; episode < specs.size(); ++episode) {
        const script::EpisodeSpec& spec = specs[episode];
        const size_t number = job_number++;
        if (plan.shard && !plan.shard->owns(number)) continue;
        Job job;
        job.spec = &spec;
        const auto id = plan.task_ids.find(spec.task);
        job.task_id = id == plan.task_ids.end() ? "" : id->second;
        job.hash = script::spec_hash(spec);
        job.policy = p;
        job.key = episode_key(spec.task, p, job.hash, spec.seed);
        list.hand_out.push_back({task, episode, policy_index});
        list.jobs.push_back(std::move(job));
      }
    }
  }
  return list;
}

}  // namespace

RunResults run_plan(const RunPlan& plan, const RunSettings& settings, const PolicyMaker& make,
                    const std::function<void(const RunProgress&)>& progress) {
  // Under mpirun the ranks other than 0 only run the episodes rank 0 hands them (eval/ranks.h).
  const Ranks ranks = mpi_ranks();
  if (ranks.distributed() && ranks.rank != 0) {
    const JobList list = plan_jobs(plan);
    std::vector<Worker> workers(static_cast<size_t>(settings.threads));
    serve_jobs(settings.threads, [&](size_t job, int worker) {
      return episode_to_json(run_one(list.jobs.at(job), settings, workers[static_cast<size_t>(worker)], make)).dump();
    });
    return RunResults{};
  }
  ReleaseWorkersOnError release(settings.threads);
  const std::vector<EpisodeResult> finished = prepare_out(settings, plan.options);
  std::map<std::string, EpisodeResult> by_key;
  for (const EpisodeResult& r : finished) by_key.emplace(episode_key(r), r);

  // The jobs not finished yet, in hand-out order.
  const JobList list = plan_jobs(plan);
  const std::vector<Job>& all_jobs = list.jobs;
  std::vector<size_t> todo;
  for (size_t j = 0; j < all_jobs.size(); ++j) {
    if (by_key.count(all_jobs[j].key) == 0) todo.push_back(j);
  }
  std::stable_sort(todo.begin(), todo.end(), [&](size_t a, size_t b) { return list.hand_out[a] < list.hand_out[b]; });

  // Run, appending each episode as it finishes.
  const fs::path lines_file = settings.out / "episodes.jsonl";
  if (settings.save_logs) fs::create_directories(settings.out / "logs");
  std::vector<Worker> workers(static_cast<size_t>(settings.threads));
  const auto start = std::chrono::steady_clock::now();
  size_t done = 0;
  const auto append = [&](const EpisodeResult& result) {
    append_episode_line(lines_file, result);
    ++done;
    if (!progress) return;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0;
    const double eta = rate > 0 ? static_cast<double>(todo.size() - done) / rate : 0;
    progress({done + finished.size(), all_jobs.size(), finished.size(), rate, eta});
  };
  std::vector<EpisodeResult> unreachable;  // in a row, held back
  std::atomic<bool> stop{false};
  std::vector<EpisodeResult> results;
  const auto finish = [&](size_t, const EpisodeResult& result) {
    if (settings.unreachable && settings.unreachable(result)) {
      unreachable.push_back(result);
      if (static_cast<int>(unreachable.size()) >= settings.max_unreachable) stop = true;
      return;
    }
    for (const EpisodeResult& held : unreachable) append(held);
    unreachable.clear();
    append(result);
  };
  try {
    if (ranks.distributed()) {
      release.disarm();
      results.resize(todo.size());
      hand_out_jobs(todo, settings.threads, [&] { return stop.load(); }, [&](size_t job, std::string_view line) {
        const std::string where = "the episode line of " + all_jobs[todo[job]].key;
        results[job] = episode_from_json(core::parse_json(line, where), where);
        finish(job, results[job]);
      });
    } else {
      results = run_jobs(
          todo.size(), settings.threads,
          [&](size_t job, int worker) {
            if (stop) throw RunStopped("stopped");
            return run_one(all_jobs[todo[job]], settings, workers[static_cast<size_t>(worker)], make);
          },
          finish);
    }
  } catch (const RunStopped&) {
    if (!stop) throw;
  }
  if (stop) {
    throw RunStopped(fmt::format("{} episodes in a row could not connect ({}); {} episodes are in {}, continue with "
                                 "--resume",
                                 settings.max_unreachable, unreachable.back().status_reason, done + finished.size(),
                                 lines_file.string()));
  }
  for (const EpisodeResult& held : unreachable) append(held);
  for (size_t i = 0; i < todo.size(); ++i) by_key.insert_or_assign(all_jobs[todo[i]].key, results[i]);

  // Results in job order whatever the completion order or resume history.
  RunResults run;
  run.info = current_run_info("none", plan.options, settings.run_options.constants);
  for (const Job& job : all_jobs) run.episodes.push_back(by_key.at(job.key));
  write_run(settings.out, run);
  return run;
}

}  // namespace hribench::eval
