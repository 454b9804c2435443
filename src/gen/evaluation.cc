#include "gen/evaluation.h"

#include <algorithm>
#include <utility>

#include "core/errors.h"
#include "core/json.h"
#include "core/paths.h"
#include "eval/episode_files.h"
#include "eval/runner.h"
#include "eval/script_contract.h"
#include "eval/shard.h"
#include "gen/pool.h"
#include "script/check.h"
#include "script/runtime.h"
#include "script/sample.h"

namespace hribench::gen {

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find(',', start), text.size());
    if (end > start) items.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return items;
}

eval::RunPlan plan_evaluation(const EvalRequest& o, const eval::PolicyMaker& make,
                              eval::RunSettings& settings) {
  // Contradictory or bad options first.
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
  if (!o.shard.empty()) eval::parse_shard(o.shard, "--shard");  // bad -> InputError before anything runs
  const std::vector<std::string> policies = split_list(o.policies);
  if (policies.empty()) throw core::InputError("--policy", "a policy list", "'" + o.policies + "'");
  for (size_t i = 0; i < policies.size(); ++i) {
    if (std::find(policies.begin(), policies.begin() + static_cast<std::ptrdiff_t>(i), policies[i]) !=
        policies.begin() + static_cast<std::ptrdiff_t>(i)) {
      throw core::InputError("--policy", "each policy once (the same policy twice runs the same episodes twice)",
                             "'" + policies[i] + "' twice");
    }
  }
  for (const std::string& p : policies) make(p);  // unknown -> InputError

  // The episodes, grouped by task: sampled seeds, or a pool's split.
  eval::RunPlan plan;
  plan.policies = policies;
  if (!o.pool.empty()) {
    if (o.sampling_flags) {
      throw core::InputError::Message("--pool", "takes its episodes from the pool; drop --episodes and --seed");
    }
    const Split split = split_from_name(o.split, "--split");
    const Manifest manifest = read_manifest(o.pool);
    const std::vector<std::string> names = o.tasks == "all" ? std::vector<std::string>{} : split_list(o.tasks);
    std::vector<script::EpisodeSpec> specs = pool_episodes(manifest, split, names);
    if (specs.empty()) {
      throw core::InputError("--tasks", "tasks of the pool", "'" + o.tasks + "' (no episodes in split " + o.split + ")");
    }
    std::vector<std::string> tasks;
    for (script::EpisodeSpec& spec : specs) {
      if (tasks.empty() || tasks.back() != spec.task) {
        tasks.push_back(spec.task);
        plan.by_task.emplace_back();
      }
      plan.by_task.back().push_back(std::move(spec));
    }
    plan.options = {{"tasks", tasks},
                    {"policies", policies},
                    {"pool", o.pool},
                    {"pool_version", manifest.pool_version},
                    {"split", o.split},
                    {"latency", eval::to_string(latency)},
                    {"horizon", o.horizon > 0 ? nlohmann::json(o.horizon) : nlohmann::json("script")}};
  } else {
    if (o.split != "eval") throw core::InputError::Message("--split", "needs --pool (a pool's split)");
    const std::vector<std::string> task_files = resolve_task_scripts(o.tasks);
    for (const std::string& file : task_files) {
      const script::Scenario scenario = script::load_scenario(core::resolve_data_path(file).string());
      plan.by_task.emplace_back();
      for (int i = 0; i < o.episodes; ++i) {
        plan.by_task.back().push_back(script::sample(scenario, o.seed + static_cast<uint64_t>(i)));
      }
    }
    plan.options = {{"tasks", task_files},    {"policies", policies},
                    {"episodes", o.episodes}, {"seed", o.seed},
                    {"latency", eval::to_string(latency)},
                    {"horizon", o.horizon > 0 ? nlohmann::json(o.horizon) : nlohmann::json("script")}};
  }
  if (!o.shard.empty()) {
    plan.shard = eval::parse_shard(o.shard, "--shard");
    size_t jobs = 0;
    for (const std::vector<script::EpisodeSpec>& specs : plan.by_task) jobs += specs.size() * policies.size();
    plan.options["shard"] = eval::to_string(*plan.shard);
    plan.options["shard_of_jobs"] = jobs;
  }
  for (const TaskFile& task : task_catalogue()) plan.task_ids.emplace(task.name, task.id);
  settings.out = o.out;
  settings.threads = o.threads;
  settings.resume = o.resume;
  settings.force = o.force;
  settings.save_logs = o.save_logs;
  settings.run_options.latency = latency;
  settings.run_options.horizon = o.horizon > 0 ? o.horizon : 0;  // 0: each script's own horizon
  return plan;
}

std::vector<std::string> tasks_ended_before_a_cue(const eval::RunPlan& plan,
                                                  const std::vector<eval::EpisodeResult>& episodes,
                                                  double horizon) {
  std::vector<std::string> tasks;
  for (const std::vector<script::EpisodeSpec>& specs : plan.by_task) {
    if (specs.empty() || !(horizon < specs.front().horizon)) continue;
    const std::string& task = specs.front().task;
    const bool any_cue = std::any_of(episodes.begin(), episodes.end(), [&](const eval::EpisodeResult& r) {
      return r.task == task && !r.metrics.cues.empty();
    });
    if (any_cue) continue;
    if (eval::contract_from_act_graph(script::compile(specs.front())).cues.empty()) continue;
    tasks.push_back(task);
  }
  return tasks;
}

LoggedEpisode load_logged_episode(const std::filesystem::path& run, const std::string& episode) {
  namespace fs = std::filesystem;
  const fs::path options_file = run / "options.json";
  if (!fs::is_regular_file(options_file)) {
    throw core::InputError(run.string(), "a run folder of hribench eval (with options.json)",
                           "no options.json");
  }
  LoggedEpisode logged;
  logged.log_file = eval::find_episode_log(run, episode, "EPISODE");
  logged.log = eval::load_episode_log(logged.log_file);

  // The spec the log ran: the pool's episode of that hash, or the task script sampled at its seed.
  const nlohmann::json options = core::read_json_file(options_file.string());
  std::vector<script::EpisodeSpec> candidates;
  if (options.contains("pool")) {
    const Manifest manifest = read_manifest(options.at("pool").get<std::string>());
    const Split split = split_from_name(options.value("split", "eval"), options_file.string() + ": split");
    candidates = pool_episodes(manifest, split, {logged.log.task});
  } else {
    for (const std::string& file : options.value("tasks", std::vector<std::string>{})) {
      const script::Scenario scenario = script::load_scenario(core::resolve_data_path(file).string());
      if (scenario.task == logged.log.task) candidates.push_back(script::sample(scenario, logged.log.seed, logged.log.robot));
    }
  }
  for (script::EpisodeSpec& spec : candidates) {
    if (script::spec_hash(spec) == logged.log.spec_hash) {
      logged.spec = std::move(spec);
      return logged;
    }
  }
  throw core::InputError(logged.log_file.string(),
                         "an episode of the run's tasks or pool (" + options_file.string() + ")",
                         "task " + logged.log.task + ", seed " + std::to_string(logged.log.seed) +
                             ", spec hash " + logged.log.spec_hash + " (none matches)");
}

eval::RunResults run_evaluation(const EvalRequest& request, const eval::PolicyMaker& make,
                                const std::function<void(const eval::RunProgress&)>& progress) {
  eval::RunSettings settings;
  const eval::RunPlan plan = plan_evaluation(request, make, settings);
  return eval::run_plan(plan, settings, make, progress);
}

}  // namespace hribench::gen
