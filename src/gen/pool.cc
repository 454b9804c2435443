#include "gen/pool.h"

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <map>
#include <numeric>
#include <set>
#include <utility>

#include "core/errors.h"
#include "core/paths.h"
#include "core/rng.h"
#include "model/robot.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::gen {
namespace {

namespace fs = std::filesystem;

uint64_t json_u64(const core::Json& value, const std::string& path) {
  if (!value.is_number_unsigned()) {
    throw core::InputError(path, "a non-negative integer", core::json_kind(value));
  }
  return value.get<uint64_t>();
}

}  // namespace

std::string released_pool() { return "pool/v" + std::to_string(kPoolVersion); }

std::string_view to_string(Split split) {
  switch (split) {
    case Split::kAdapt: return "adapt";
    case Split::kEval: return "eval";
    case Split::kTest: return "test";
  }
  return "?";
}

Split split_from_name(std::string_view name, std::string_view where) {
  for (const Split s : {Split::kAdapt, Split::kEval, Split::kTest}) {
    if (to_string(s) == name) return s;
  }
  throw core::InputError(std::string(where), "adapt, eval or test", "'" + std::string(name) + "'");
}

uint64_t candidate_seed(uint64_t seed, std::string_view task, size_t index) {
  core::Rng rng = core::Rng(seed).split("candidates").split(task).split(static_cast<uint64_t>(index));
  return rng.next_u64() >> 16;
}

std::vector<Split> assign_splits(size_t validated, uint64_t seed, std::string_view task,
                                 const SplitSizes& sizes) {
  HRIB_CHECK(validated >= sizes.total()) << validated << " < " << sizes.total();
  // Fisher-Yates with our own RNG (std::shuffle differs between standard libraries).
  std::vector<size_t> order(validated);
  std::iota(order.begin(), order.end(), size_t{0});
  core::Rng rng = core::Rng(seed).split("splits").split(task);
  for (size_t i = validated; i > 1; --i) {
    const size_t j = static_cast<size_t>(rng.uniform_int(0, static_cast<int64_t>(i) - 1));
    std::swap(order[i - 1], order[j]);
  }
  std::vector<Split> splits(validated, Split::kTest);
  for (size_t k = 0; k < validated; ++k) {
    if (k < sizes.adapt) {
      splits[order[k]] = Split::kAdapt;
    } else if (k < sizes.adapt + sizes.eval) {
      splits[order[k]] = Split::kEval;
    }
  }
  return splits;
}

core::Json to_json(const Manifest& manifest) {
  core::Json episodes = core::Json::array();
  for (const PoolEntry& e : manifest.episodes) {
    episodes.push_back({{"task", e.task},
                        {"script", e.script},
                        {"split", std::string(to_string(e.split))},
                        {"candidate", e.candidate},
                        {"seed", e.seed},
                        {"hash", e.hash}});
  }
  return {{"pool_version", manifest.pool_version},
          {"generator", manifest.generator},
          {"episodes", episodes}};
}

Manifest manifest_from_json(const core::Json& json, std::string_view source) {
  const std::string where = std::string(source);
  if (!json.is_object()) throw core::InputError(where, "a pool manifest object", core::json_kind(json));
  Manifest manifest;
  const core::Json& version = core::json_member(json, "pool_version", where);
  if (!version.is_number_integer() || version.get<int>() != kPoolVersion) {
    throw core::InputError(where + " (pool_version)", "pool version " + std::to_string(kPoolVersion),
                           version.dump());
  }
  manifest.pool_version = kPoolVersion;
  manifest.generator = core::json_member(json, "generator", where);
  if (!manifest.generator.is_object()) {
    throw core::InputError(where + " (generator)", "an object", core::json_kind(manifest.generator));
  }
  const std::string robot_where = where + " (generator.robot)";
  const std::string robot =
      core::json_string(core::json_member(manifest.generator, "robot", where + " (generator)"), robot_where);
  try {
    model::robot_by_name(robot);
  } catch (const core::InputError& e) {
    throw core::InputError(robot_where, e.expected(), e.got());
  }
  const core::Json& episodes = core::json_member(json, "episodes", where);
  if (!episodes.is_array()) throw core::InputError(where + " (episodes)", "an array", core::json_kind(episodes));
  std::set<std::pair<std::string, uint64_t>> seeds;
  for (size_t i = 0; i < episodes.size(); ++i) {
    const std::string path = where + " (episodes[" + std::to_string(i) + "])";
    const core::Json& e = episodes[i];
    PoolEntry entry;
    entry.task = core::json_string(core::json_member(e, "task", path), path + ".task");
    entry.script = core::json_string(core::json_member(e, "script", path), path + ".script");
    entry.split = split_from_name(core::json_string(core::json_member(e, "split", path), path + ".split"),
                                  path + ".split");
    entry.candidate = json_u64(core::json_member(e, "candidate", path), path + ".candidate");
    entry.seed = json_u64(core::json_member(e, "seed", path), path + ".seed");
    entry.hash = core::json_string(core::json_member(e, "hash", path), path + ".hash");
    if (!seeds.emplace(entry.task, entry.seed).second) {
      throw core::InputError::Message(path + ".seed", "seed " + std::to_string(entry.seed) +
                                                          " of " + entry.task + " appears twice");
    }
    manifest.episodes.push_back(std::move(entry));
  }
  return manifest;
}

std::string pool_robot(const Manifest& manifest) { return manifest.generator.at("robot").get<std::string>(); }

Manifest read_manifest(const std::string& dir) {
  const fs::path path = core::resolve_data_path(fs::path(dir) / "manifest.json");
  if (!fs::is_regular_file(path)) {
    throw core::InputError::Message(dir, "holds no pool (no manifest.json)");
  }
  return manifest_from_json(core::read_json_file(path.string()), path.string());
}

std::vector<TaskFile> task_catalogue() {
  const fs::path dir = core::data_root() / "tasks";
  std::vector<TaskFile> tasks;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return tasks;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    const std::string stem = entry.path().stem().string();
    const size_t cut = stem.find('_');
    TaskFile task;
    task.id = cut == std::string::npos ? stem : stem.substr(0, cut);
    task.name = cut == std::string::npos ? stem : stem.substr(cut + 1);
    task.script = (fs::path("tasks") / entry.path().filename()).string();
    tasks.push_back(std::move(task));
  }
  std::sort(tasks.begin(), tasks.end(),
            [](const TaskFile& a, const TaskFile& b) { return a.script < b.script; });
  return tasks;
}

std::string task_list_text() {
  std::string text;
  for (const TaskFile& task : task_catalogue()) {
    text += (text.empty() ? "" : ", ") + task.id + " " + task.name;
  }
  return text;
}

std::vector<std::string> resolve_task_scripts(const std::string& list) {
  const std::vector<TaskFile> all = task_catalogue();
  const auto expected = [&] {
    return all.empty() ? "a task script file (no tasks/ folder under the data root " +
                             core::data_root().string() + "; set --root or HRIBENCH_ROOT)"
                       : "a task id or name (" + task_list_text() + "), a script file or all";
  };
  std::vector<std::string> paths;
  std::stringstream stream(list);
  std::string name;
  while (std::getline(stream, name, ',')) {
    if (name.empty()) continue;
    if (name == "all") {
      if (all.empty()) throw core::InputError("--tasks", expected(), "'all'");
      for (const TaskFile& task : all) paths.push_back(task.script);
      continue;
    }
    const auto found = std::find_if(all.begin(), all.end(), [&](const TaskFile& task) {
      return name == task.id || name == task.name || name == task.id + "_" + task.name ||
             fs::path(name).lexically_normal() == fs::path(task.script);
    });
    if (found != all.end()) {
      paths.push_back(found->script);
    } else if (fs::is_regular_file(name)) {
      paths.push_back(name);
    } else {
      throw core::InputError("--tasks", expected(), "'" + name + "'");
    }
  }
  if (paths.empty()) throw core::InputError("--tasks", "a task list", "'" + list + "'");
  return paths;
}

std::vector<script::EpisodeSpec> pool_episodes(const Manifest& manifest, Split split,
                                               const std::vector<std::string>& tasks) {
  // A name matches an entry by task name, script file, or script stem, its prefix or suffix
  // (as resolve_task_scripts matches the files of tasks/).
  const auto matches = [](const std::string& name, const PoolEntry& e) {
    const std::string stem = fs::path(e.script).stem().string();
    const std::string suffix = "_" + name;
    return name == e.task || name == stem || stem.rfind(name + "_", 0) == 0 ||
           (stem.size() > suffix.size() &&
            stem.compare(stem.size() - suffix.size(), suffix.size(), suffix) == 0) ||
           fs::path(name).lexically_normal() == fs::path(e.script).lexically_normal();
  };
  for (const std::string& t : tasks) {
    const bool known = std::any_of(manifest.episodes.begin(), manifest.episodes.end(),
                                   [&](const PoolEntry& e) { return matches(t, e); });
    if (!known) throw core::InputError("--tasks", "a task of the pool", "'" + t + "'");
  }
  const auto wanted = [&](const PoolEntry& e) {
    if (tasks.empty()) return true;
    return std::any_of(tasks.begin(), tasks.end(), [&](const std::string& t) { return matches(t, e); });
  };
  std::map<std::string, script::Scenario> scenarios;
  std::vector<script::EpisodeSpec> specs;
  for (const PoolEntry& e : manifest.episodes) {
    if (e.split != split || !wanted(e)) continue;
    auto it = scenarios.find(e.script);
    if (it == scenarios.end()) {
      it = scenarios.emplace(e.script, script::load_scenario(core::resolve_data_path(e.script).string())).first;
    }
    script::EpisodeSpec spec = script::sample(it->second, e.seed, pool_robot(manifest));
    const std::string hash = script::spec_hash(spec);
    if (hash != e.hash) {
      throw core::InputError::Message(
          e.script + " (seed " + std::to_string(e.seed) + ")",
          "samples an episode whose hash differs from the pool manifest's (" + hash.substr(0, 12) +
              " vs " + e.hash.substr(0, 12) +
              "): the pool was made from other scripts or another sampler; regenerate it and bump "
              "the pool version");
    }
    specs.push_back(std::move(spec));
  }
  return specs;
}

}  // namespace hribench::gen
