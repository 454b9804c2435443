#include "gen/pool.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "core/errors.h"
#include "script/check.h"
#include "script/sample.h"
#include "support/test_files.h"

namespace hribench::gen {
namespace {

using ::testing::HasSubstr;

using ::hribench::testing::error_of;

TEST(Pool, SplitNamesRoundTripAndOthersAreRefused) {
  for (const Split s : {Split::kAdapt, Split::kEval, Split::kTest}) {
    EXPECT_EQ(split_from_name(to_string(s), "--split"), s);
  }
  EXPECT_EQ(error_of([] { split_from_name("train", "--split"); }),
            "--split: expected adapt, eval or test, got 'train'");
}

TEST(Pool, CandidateSeedsAreDeterministicDistinctAnd48Bit) {
  std::set<uint64_t> seen;
  for (size_t i = 0; i < 500; ++i) {
    const uint64_t s = candidate_seed(7, "point_pick", i);
    EXPECT_EQ(s, candidate_seed(7, "point_pick", i));
    EXPECT_LT(s, uint64_t{1} << 48);
    seen.insert(s);
  }
  EXPECT_EQ(seen.size(), 500u);
  EXPECT_NE(candidate_seed(7, "point_pick", 0), candidate_seed(8, "point_pick", 0));
  EXPECT_NE(candidate_seed(7, "point_pick", 0), candidate_seed(7, "stop_go", 0));
}

TEST(Pool, SplitsHaveTheirSizesAndAreDeterministic) {
  const SplitSizes sizes{5, 3, 2};
  const std::vector<Split> a = assign_splits(14, 1, "stop_go", sizes);
  EXPECT_EQ(a, assign_splits(14, 1, "stop_go", sizes));
  EXPECT_NE(a, assign_splits(14, 2, "stop_go", sizes));
  EXPECT_EQ(std::count(a.begin(), a.end(), Split::kAdapt), 5);
  EXPECT_EQ(std::count(a.begin(), a.end(), Split::kEval), 3);
  EXPECT_EQ(std::count(a.begin(), a.end(), Split::kTest), 6);  // the rest
}

Manifest small_manifest() {
  Manifest m;
  m.generator = {{"seed", 3}, {"robot", "panda"}};
  m.episodes.push_back({"point_pick", "tasks/I1_point_pick.yaml", Split::kEval, 4, 123456789012345ULL, "ab"});
  m.episodes.push_back({"point_pick", "tasks/I1_point_pick.yaml", Split::kAdapt, 9, 42, "cd"});
  return m;
}

TEST(Pool, ManifestRoundTripsThroughJson) {
  const Manifest m = small_manifest();
  const Manifest back = manifest_from_json(to_json(m), "manifest.json");
  ASSERT_EQ(back.episodes.size(), 2u);
  EXPECT_EQ(back.episodes[0].seed, 123456789012345ULL);
  EXPECT_EQ(back.episodes[0].split, Split::kEval);
  EXPECT_EQ(back.episodes[1].candidate, 9u);
  EXPECT_EQ(back.episodes[1].hash, "cd");
  EXPECT_EQ(back.generator, m.generator);
  EXPECT_EQ(to_json(back), to_json(m));
}

TEST(Pool, ManifestOfAnotherVersionOrWithSharedSeedsIsRefused) {
  core::Json json = to_json(small_manifest());
  json["pool_version"] = kPoolVersion + 1;
  EXPECT_EQ(error_of([&] { manifest_from_json(json, "m.json"); }),
            "m.json (pool_version): expected pool version " + std::to_string(kPoolVersion) + ", got " +
                std::to_string(kPoolVersion + 1));
  json = to_json(small_manifest());
  json["episodes"][1]["seed"] = 123456789012345ULL;
  EXPECT_THAT(error_of([&] { manifest_from_json(json, "m.json"); }), HasSubstr("appears twice"));
  json = to_json(small_manifest());
  json["episodes"][0]["split"] = "train";
  EXPECT_THAT(error_of([&] { manifest_from_json(json, "m.json"); }),
              HasSubstr("m.json (episodes[0]).split: expected adapt, eval or test"));
  EXPECT_THAT(error_of([] { read_manifest("/nonexistent-pool"); }), HasSubstr("holds no pool"));
}

TEST(Pool, ManifestNamesAKnownRobot) {
  EXPECT_EQ(pool_robot(manifest_from_json(to_json(small_manifest()), "m.json")), "panda");
  core::Json json = to_json(small_manifest());
  json["generator"].erase("robot");
  EXPECT_THAT(error_of([&] { manifest_from_json(json, "m.json"); }), HasSubstr("m.json (generator)"));
  EXPECT_THAT(error_of([&] { manifest_from_json(json, "m.json"); }), HasSubstr("robot"));
  json["generator"]["robot"] = "ur5";
  EXPECT_EQ(error_of([&] { manifest_from_json(json, "m.json"); }),
            "m.json (generator.robot): expected one of panda, got 'ur5'");
}

TEST(Pool, EpisodesAreResampledAndCheckedAgainstTheManifestHash) {
  const script::Scenario scenario = script::load_scenario("tasks/I1_point_pick.yaml");
  Manifest m;
  m.generator = {{"robot", "panda"}};
  const uint64_t seed = candidate_seed(0, "point_pick", 3);
  m.episodes.push_back({"point_pick", "tasks/I1_point_pick.yaml", Split::kEval, 3, seed,
                        script::spec_hash(script::sample(scenario, seed))});
  m.episodes.push_back({"point_pick", "tasks/I1_point_pick.yaml", Split::kAdapt, 5, seed + 1, "x"});
  const std::vector<script::EpisodeSpec> eval = pool_episodes(m, Split::kEval);
  ASSERT_EQ(eval.size(), 1u);
  EXPECT_EQ(eval[0].seed, seed);
  EXPECT_TRUE(pool_episodes(m, Split::kTest).empty());
  EXPECT_EQ(pool_episodes(m, Split::kEval, {"I1"}).size(), 1u);
  EXPECT_EQ(pool_episodes(m, Split::kEval, {"pick"}).size(), 1u);
  EXPECT_EQ(pool_episodes(m, Split::kEval, {"./tasks/I1_point_pick.yaml"}).size(), 1u);
  // A name the pool does not have is an error, also beside one it has.
  EXPECT_EQ(error_of([&] { pool_episodes(m, Split::kEval, {"I1", "stop_go"}); }),
            "--tasks: expected a task of the pool, got 'stop_go'");
  // A hash that does not match: the scripts changed since the pool was made.
  EXPECT_THAT(error_of([&] { pool_episodes(m, Split::kAdapt); }),
              HasSubstr("hash differs from the pool manifest's"));
}

TEST(Pool, TaskListsResolveToScripts) {
  const std::vector<std::string> all = resolve_task_scripts("all");
  EXPECT_EQ(all.size(), 13u);
  EXPECT_TRUE(std::is_sorted(all.begin(), all.end()));
  EXPECT_EQ(resolve_task_scripts("I1,stop_go"),
            (std::vector<std::string>{"tasks/I1_point_pick.yaml", "tasks/I4_stop_go.yaml"}));
  EXPECT_EQ(error_of([] { resolve_task_scripts("Z9"); }),
            "--tasks: expected a task id or name (C1 handover_h2r, C2 handover_r2h, C3 box_retrieval, C4 co_lift, "
            "I1 point_pick, I2 gesture_delivery, I3 demo_imitate, I4 stop_go, I5 contradiction, X1 intrusion_yield, "
            "X2 object_moved, X3 someone_else_places, X4 blocked_target), a script file or all, got 'Z9'");
  EXPECT_EQ(error_of([] { resolve_task_scripts(","); }), "--tasks: expected a task list, got ','");
}

}  // namespace
}  // namespace hribench::gen
