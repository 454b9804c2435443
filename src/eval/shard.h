#pragma once
// Sharded runs (docs/scale.md): `hribench eval --shard i/N` runs the jobs j of the full job list
// (task, policy, episode order) with j mod N = i, and records "shard": "i/N" and "shard_of_jobs"
// (the full list's length, so a merge can tell that every shard holds its share) in its options;
// merge_shards combines the N shard runs into exactly the run one process would have written
// (episodes in job order; the same options, provenance and constants), or refuses shards that
// disagree.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "eval/report.h"

namespace hribench::eval {

struct Shard {
  int index = 0;  // i, 0 <= i < count
  int count = 1;  // N
  // Whether job number `job` of the full job list is this shard's.
  bool owns(size_t job) const { return job % static_cast<size_t>(count) == static_cast<size_t>(index); }
};

// "i/N" with whole numbers 0 <= i < N <= 100000; throws core::InputError (where = `where`) otherwise.
Shard parse_shard(std::string_view text, std::string_view where);
std::string to_string(const Shard& shard);  // "i/N"

// One shard's folder (for messages) and options (options.json).
struct ShardOptions {
  std::string dir;
  nlohmann::json options;
};

// Checks the folders of a sharded job (eval or generate) and returns their positions in shard
// order (element i: the folder of shard i/N). Throws core::InputError naming the folder and
// what differs when a folder is not a shard (no "shard" and "shard_of_jobs"), the shards do
// not cover 0..N-1 once each, or their options (other than the shard) or job counts differ.
std::vector<size_t> shard_order(const std::vector<ShardOptions>& shards);
// How many of `jobs` jobs shard i/N holds (the jobs i, i + N, i + 2N, ...).
size_t shard_share(size_t jobs, const Shard& shard);
// The options of the whole job: a shard's options without "shard" and "shard_of_jobs".
nlohmann::json merged_options(const nlohmann::json& shard_options);

// One finished shard run: its folder (for messages), options.json and results.
struct ShardRun {
  std::string dir;
  nlohmann::json options;
  RunResults results;
};

// The run one process would have written. Throws core::InputError naming the folder and what
// differs when a folder is not a shard run, the shards do not cover 0..N-1 once each, their
// options (other than the shard), job count, HRIBench version, git hash, MuJoCo version,
// renderer or metric constants differ, or a shard holds another number of episodes than its
// share.
RunResults merge_shards(const std::vector<ShardRun>& shards);

}  // namespace hribench::eval
