#include "io/replay.h"

#include <fstream>
#include <map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "eval/episode.h"
#include "gen/pool.h"
#include "io/collect.h"
#include "io/hdf5.h"
#include "io/lerobot.h"
#include "policy/registry.h"
#include "script/sample.h"

namespace hribench::io {

namespace fs = std::filesystem;

namespace {

nlohmann::json collect_options(const fs::path& dir) {
  const fs::path path = collect_state_path(dir);
  std::ifstream in(path);
  if (!in) throw core::InputError("--dataset", "a folder written by hribench collect (hribench/collect.json)", "'" + dir.string() + "'");
  const nlohmann::json state = nlohmann::json::parse(in, nullptr, false);
  if (state.is_discarded() || !state.contains("options")) {
    throw core::InputError(path.string(), "a collect's state (options, episodes)", "other content");
  }
  return state.at("options");
}

}  // namespace

std::vector<RecordedEpisode> read_recorded_episodes(const fs::path& dir) {
  const nlohmann::json options = collect_options(dir);
  const std::string format = options.value("format", "");
  if (format == "act-hdf5") return read_act_episodes(dir, options.at("tasks").get<std::vector<std::string>>());
  if (format == "robomimic") return read_robomimic_episodes(dir);
  if (format == "lerobot" || format == "lerobot-v3") {
    std::vector<RecordedEpisode> recorded;
    for (LeRobotEpisode& episode : read_lerobot_episodes(dir)) {
      RecordedEpisode r{episode.task, episode.spec_hash, episode.seed, episode.policy,
                        policy::action_space_from_string(episode.action_space, dir.string() + ": action_space"),
                        std::move(episode.actions)};
      // The last row records the command in force, held: it was never executed (recording.h).
      if (!r.actions.empty()) r.actions.pop_back();
      recorded.push_back(std::move(r));
    }
    return recorded;
  }
  throw core::InputError("--dataset", "a dataset of a format with a reader (lerobot, lerobot-v3, act-hdf5, robomimic)",
                         "format '" + format + "'");
}

eval::EpisodeLog replay_episode(const script::EpisodeSpec& spec, const RecordedEpisode& recorded) {
  const std::string where = fmt::format("replay of {} seed {}", recorded.task, recorded.seed);
  const std::string hash = script::spec_hash(spec);
  if (hash != recorded.spec_hash) throw core::InputError(where, "spec " + recorded.spec_hash, "spec " + hash);
  policy::PolicySpec policy;
  policy.action_space = recorded.action_space;
  eval::RunOptions options;
  options.horizon = 0;  // the script's, as the collect
  eval::Episode episode(spec, policy, eval::setup_of(spec, recorded.policy), options);
  episode.reset();
  std::string end;  // why it ended
  for (size_t k = 0; k < recorded.actions.size(); ++k) {
    if (episode.done()) {
      throw core::InputError(where, fmt::format("an episode that runs {} actions", recorded.actions.size()),
                             fmt::format("one that ended after {} ({})", k, end));
    }
    const std::vector<float>& a = recorded.actions[k];
    end = episode.step(policy::Action(a.begin(), a.end())).info;
  }
  if (!episode.done()) {
    throw core::InputError(where, fmt::format("an episode that ends after its {} actions", recorded.actions.size()),
                           "one still running");
  }
  return episode.log();
}

ReplayReport replay_dataset(const fs::path& dir, size_t limit) {
  const nlohmann::json options = collect_options(dir);
  // Only the policy's own actions are the executed ones.
  const std::string policy = options.at("policy").get<std::string>();
  const std::string own(policy::to_string(policy::make_policy(policy)->spec().action_space));
  if (options.at("action_space") != own) {
    throw core::InputError("--dataset", "a dataset of " + policy + "'s own actions (" + own + ")",
                           options.at("action_space").dump() + " actions (--action-space)");
  }
  const gen::Manifest manifest = gen::read_manifest(options.at("pool").get<std::string>());
  const gen::Split split = gen::split_from_name(options.at("split").get<std::string>(), "split");
  const std::vector<script::EpisodeSpec> specs =
      gen::pool_episodes(manifest, split, options.at("tasks").get<std::vector<std::string>>());
  std::map<std::string, const script::EpisodeSpec*> by_hash;
  for (const script::EpisodeSpec& spec : specs) by_hash.emplace(script::spec_hash(spec), &spec);
  ReplayReport report;
  for (const RecordedEpisode& recorded : read_recorded_episodes(dir)) {
    if (limit > 0 && report.episodes >= limit) break;
    ++report.episodes;
    const std::string name = fmt::format("{} seed {}", recorded.task, recorded.seed);
    const auto spec = by_hash.find(recorded.spec_hash);
    if (spec == by_hash.end()) {
      report.differing.push_back(name + ": its spec is not in the pool's split");
      continue;
    }
    const fs::path log_file = collect_log_path(dir, recorded.task, recorded.seed, recorded.spec_hash);
    try {
      const eval::EpisodeLog replayed = replay_episode(*spec->second, recorded);
      if (eval::identical(replayed, eval::load_episode_log(log_file))) {
        ++report.identical;
      } else {
        report.differing.push_back(name + ": the replayed log differs from " + log_file.string());
      }
    } catch (const core::InputError& e) {
      report.differing.push_back(name + ": " + e.what());
    }
  }
  return report;
}

}  // namespace hribench::io
