#include "eval/shard.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "core/errors.h"

namespace hribench::eval {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Shard, ParsesIOfNAndOwnsEveryNthJob) {
  const Shard s = parse_shard("1/3", "--shard");
  EXPECT_EQ(s.index, 1);
  EXPECT_EQ(s.count, 3);
  EXPECT_EQ(to_string(s), "1/3");
  std::vector<size_t> owned;
  for (size_t job = 0; job < 8; ++job) {
    if (s.owns(job)) owned.push_back(job);
  }
  EXPECT_EQ(owned, (std::vector<size_t>{1, 4, 7}));
  for (const char* bad : {"3/3", "-1/3", "1/0", "1", "a/b", "1/3x", "", "0/100001"}) {
    EXPECT_EQ(error_of([&] { parse_shard(bad, "--shard"); }),
              std::string("--shard: expected i/N with 0 <= i < N <= 100000 (e.g. 0/4), got '") + bad + "'")
        << bad;
  }
}

// Runs of 5 episodes (seeds 0..4) split into 2 shards.
std::vector<ShardRun> two_shards() {
  RunResults full;
  full.info = current_run_info("none", {{"episodes", 5}});
  for (uint64_t seed = 0; seed < 5; ++seed) {
    EpisodeResult r;
    r.task = "stop_go";
    r.role = "instructor";
    r.policy = "noop";
    r.seed = seed;
    full.episodes.push_back(r);
  }
  std::vector<ShardRun> shards;
  for (int i = 0; i < 2; ++i) {
    ShardRun s{"runs/s" + std::to_string(i),
               {{"episodes", 5}, {"shard", std::to_string(i) + "/2"}, {"shard_of_jobs", 5}},
               full};
    s.results.info.options = s.options;
    s.results.episodes.clear();
    for (size_t job = 0; job < 5; ++job) {
      if (job % 2 == static_cast<size_t>(i)) s.results.episodes.push_back(full.episodes[job]);
    }
    shards.push_back(s);
  }
  return shards;
}

TEST(Shard, MergeInterleavesIntoJobOrderWithoutTheShardOption) {
  std::vector<ShardRun> shards = two_shards();
  std::swap(shards[0], shards[1]);  // any order of folders
  const RunResults merged = merge_shards(shards);
  ASSERT_EQ(merged.episodes.size(), 5u);
  for (uint64_t seed = 0; seed < 5; ++seed) EXPECT_EQ(merged.episodes[seed].seed, seed);
  EXPECT_EQ(merged.info.options, nlohmann::json({{"episodes", 5}}));
}

TEST(Shard, MergeRefusesShardsThatDisagree) {
  auto shards = two_shards();
  shards[1].options["horizon"] = 2;
  EXPECT_EQ(error_of([&] { merge_shards(shards); }), "runs/s1: ran with other options than runs/s0 (horizon)");
  shards = two_shards();
  shards[1].results.info.git_hash = "abc";
  EXPECT_EQ(error_of([&] { merge_shards(shards); }),
            "runs/s1: was made by other code than runs/s0: git hash abc (not " + shards[0].results.info.git_hash + ")");
  shards = two_shards();
  shards[1].results.info.constants.still_sustain = 0.3;
  EXPECT_EQ(error_of([&] { merge_shards(shards); }),
            "runs/s1: was made by other code than runs/s0: other metric constants");
  shards = two_shards();
  EXPECT_EQ(error_of([&] { merge_shards({shards[0]}); }), "merge: shard 1/2 is missing");
  EXPECT_EQ(error_of([&] { merge_shards({shards[0], shards[0]}); }), "runs/s0: is shard 0/2 again (runs/s0 is too)");
  shards[1].options["shard"] = "1/3";
  EXPECT_EQ(error_of([&] { merge_shards(shards); }), "runs/s1: is shard 1/3 of another split than runs/s0 (2 shards)");
  shards = two_shards();
  shards[0].results.episodes.pop_back();  // an episode lost
  EXPECT_EQ(error_of([&] { merge_shards(shards); }), "runs/s0: holds 2 episodes, expected 3 (shard 0/2 of 5 jobs)");
  shards = two_shards();
  shards[1].options["shard_of_jobs"] = 6;
  EXPECT_EQ(error_of([&] { merge_shards(shards); }), "runs/s1: is a shard of 6 jobs, runs/s0 of 5");
  shards[0].options.erase("shard");
  EXPECT_EQ(error_of([&] { merge_shards(shards); }),
            "runs/s0: is not a shard run (its options have no \"shard\" and \"shard_of_jobs\")");
}

}  // namespace
}  // namespace hribench::eval
