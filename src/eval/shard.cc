#include "eval/shard.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <optional>
#include <set>
#include <utility>

#include <fmt/format.h>

#include "core/errors.h"
#include "eval/constants.h"

namespace hribench::eval {
namespace {

constexpr int kMaxShards = 100000;

std::optional<int> whole(std::string_view text) {
  int value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || text.front() == '-') {
    return std::nullopt;
  }
  return value;
}

// The first provenance field or constant in which `run` differs from `first`, or "".
std::string provenance_difference(const RunResults& run, const RunResults& first) {
  const std::pair<const char*, std::pair<const std::string*, const std::string*>> fields[] = {
      {"HRIBench version", {&run.info.hribench_version, &first.info.hribench_version}},
      {"git hash", {&run.info.git_hash, &first.info.git_hash}},
      {"MuJoCo version", {&run.info.mujoco_version, &first.info.mujoco_version}},
      {"renderer", {&run.info.renderer, &first.info.renderer}}};
  for (const auto& [name, values] : fields) {
    if (*values.first != *values.second) return fmt::format("{} {} (not {})", name, *values.first, *values.second);
  }
  if (constant_table(run.info.constants) != constant_table(first.info.constants)) return "other metric constants";
  return "";
}

}  // namespace

Shard parse_shard(std::string_view text, std::string_view where) {
  const size_t slash = text.find('/');
  const std::optional<int> i = slash == std::string_view::npos ? std::nullopt : whole(text.substr(0, slash));
  const std::optional<int> n = slash == std::string_view::npos ? std::nullopt : whole(text.substr(slash + 1));
  if (!i || !n || *n < 1 || *n > kMaxShards || *i >= *n) {
    throw core::InputError(std::string(where), fmt::format("i/N with 0 <= i < N <= {} (e.g. 0/4)", kMaxShards),
                           "'" + std::string(text) + "'");
  }
  return Shard{*i, *n};
}

std::string to_string(const Shard& shard) { return fmt::format("{}/{}", shard.index, shard.count); }

nlohmann::json merged_options(const nlohmann::json& shard_options) {
  nlohmann::json options = shard_options;
  options.erase("shard");
  options.erase("shard_of_jobs");
  return options;
}

size_t shard_share(size_t jobs, const Shard& shard) {
  const size_t n = static_cast<size_t>(shard.count);
  return jobs / n + (static_cast<size_t>(shard.index) < jobs % n ? 1 : 0);
}

std::vector<size_t> shard_order(const std::vector<ShardOptions>& shards) {
  if (shards.empty()) throw core::InputError("merge", "shard folders", "none");
  std::vector<std::optional<size_t>> by_index;
  for (size_t k = 0; k < shards.size(); ++k) {
    const ShardOptions& s = shards[k];
    if (!s.options.contains("shard") || !s.options.at("shard").is_string() ||
        !s.options.contains("shard_of_jobs") || !s.options.at("shard_of_jobs").is_number_integer() ||
        s.options.at("shard_of_jobs").get<int64_t>() < 0) {
      throw core::InputError::Message(s.dir, "is not a shard run (its options have no \"shard\" and \"shard_of_jobs\")");
    }
    const Shard shard = parse_shard(s.options.at("shard").get<std::string>(), s.dir + " (options.json shard)");
    if (by_index.empty()) by_index.assign(static_cast<size_t>(shard.count), std::nullopt);
    if (static_cast<size_t>(shard.count) != by_index.size()) {
      throw core::InputError::Message(s.dir, fmt::format("is shard {} of another split than {} ({} shards)",
                                                         to_string(shard), shards.front().dir, by_index.size()));
    }
    std::optional<size_t>& slot = by_index[static_cast<size_t>(shard.index)];
    if (slot) {
      throw core::InputError::Message(s.dir, fmt::format("is shard {} again ({} is too)", to_string(shard), shards[*slot].dir));
    }
    slot = k;
  }
  std::vector<size_t> order;
  for (size_t i = 0; i < by_index.size(); ++i) {
    if (!by_index[i]) throw core::InputError::Message("merge", fmt::format("shard {}/{} is missing", i, by_index.size()));
    order.push_back(*by_index[i]);
  }
  const ShardOptions& first = shards[order.front()];
  const nlohmann::json expected = merged_options(first.options);
  for (const size_t k : order) {
    const ShardOptions& s = shards[k];
    const nlohmann::json options = merged_options(s.options);
    if (options != expected) {
      std::set<std::string> keys;
      for (const auto& [key, value] : options.items()) keys.insert(key);
      for (const auto& [key, value] : expected.items()) keys.insert(key);
      std::string differing;
      for (const std::string& key : keys) {
        if (options.value(key, nlohmann::json()) != expected.value(key, nlohmann::json())) {
          differing += (differing.empty() ? "" : ", ") + key;
        }
      }
      throw core::InputError::Message(s.dir, "ran with other options than " + first.dir + " (" + differing + ")");
    }
    if (s.options.at("shard_of_jobs") != first.options.at("shard_of_jobs")) {
      throw core::InputError::Message(s.dir, fmt::format("is a shard of {} jobs, {} of {}", s.options.at("shard_of_jobs").dump(),
                                                          first.dir, first.options.at("shard_of_jobs").dump()));
    }
  }
  return order;
}

RunResults merge_shards(const std::vector<ShardRun>& shards) {
  std::vector<ShardOptions> folders;
  for (const ShardRun& s : shards) folders.push_back({s.dir, s.options});
  const std::vector<size_t> order = shard_order(folders);
  const ShardRun& first = shards[order.front()];
  for (const size_t k : order) {
    if (const std::string d = provenance_difference(shards[k].results, first.results); !d.empty()) {
      throw core::InputError::Message(shards[k].dir, "was made by other code than " + first.dir + ": " + d);
    }
  }
  // Shard i holds the jobs i, i + N, i + 2N, ... of the full list.
  const size_t n = order.size();
  const size_t total = first.options.at("shard_of_jobs").get<size_t>();
  RunResults merged;
  merged.info = first.results.info;
  merged.info.options = merged_options(first.options);
  for (size_t i = 0; i < n; ++i) {
    const ShardRun& s = shards[order[i]];
    const size_t share = shard_share(total, Shard{static_cast<int>(i), static_cast<int>(n)});
    if (s.results.episodes.size() != share) {
      throw core::InputError::Message(
          s.dir, fmt::format("holds {} episodes, expected {} (shard {}/{} of {} jobs)", s.results.episodes.size(), share, i, n, total));
    }
  }
  for (size_t job = 0; job < total; ++job) merged.episodes.push_back(shards[order[job % n]].results.episodes[job / n]);
  return merged;
}

}  // namespace hribench::eval
