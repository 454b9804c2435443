// Tests of replay_episode (io/replay.h) on actions taken from a short oracle episode run with
// float32 actions: they reproduce its log bit for bit; one action changed by one float step
// does not; too few or too many actions, and another spec, are refused with a message.

#include "io/replay.h"

#include <gtest/gtest.h>

#include <cmath>

#include "eval/runner.h"
#include "gen/pool.h"
#include "io/collect.h"
#include "policy/registry.h"
#include "script/sample.h"
#include "support/test_files.h"

namespace hribench::io {
namespace {

using ::hribench::testing::error_of;

class ReplayTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    specs_ = gen::pool_episodes(gen::read_manifest(gen::released_pool()), gen::Split::kAdapt, {"handover_r2h"});
    // The oracle to its end (the script's horizon, as a collect runs it), float32 actions.
    Float32Actions policy(policy::make_policy("oracle"));
    eval::RunOptions options;
    options.horizon = 0;
    eval::Episode episode(specs_[0], policy.spec(), eval::setup_of(specs_[0], "oracle"), options);
    log_ = eval::run_episode(episode, policy);
    recorded_.task = specs_[0].task;
    recorded_.spec_hash = script::spec_hash(specs_[0]);
    recorded_.seed = specs_[0].seed;
    recorded_.policy = "oracle";
    for (size_t k = 1; k < log_.steps.size(); ++k) {
      recorded_.actions.emplace_back(log_.steps[k].action.begin(), log_.steps[k].action.end());
    }
  }
  static inline std::vector<script::EpisodeSpec> specs_;
  static inline eval::EpisodeLog log_;
  static inline RecordedEpisode recorded_;
};

TEST_F(ReplayTest, TheExecutedActionsReproduceTheLogBitForBit) {
  EXPECT_TRUE(eval::identical(replay_episode(specs_[0], recorded_), log_));
}

TEST_F(ReplayTest, OneActionChangedByOneFloatStepChangesTheLog) {
  RecordedEpisode changed = recorded_;
  changed.actions[10][0] = std::nextafter(changed.actions[10][0], 1.0f);
  EXPECT_FALSE(eval::identical(replay_episode(specs_[0], changed), log_));
}

TEST_F(ReplayTest, RefusesActionsThatDoNotFitTheEpisode) {
  const std::string name = "replay of handover_r2h seed " + std::to_string(recorded_.seed);
  RecordedEpisode shorter = recorded_;
  shorter.actions.resize(5);
  EXPECT_EQ(error_of([&] { replay_episode(specs_[0], shorter); }),
            name + ": expected an episode that ends after its 5 actions, got one still running");
  RecordedEpisode longer = recorded_;
  longer.actions.push_back(longer.actions.back());
  EXPECT_NE(error_of([&] { replay_episode(specs_[0], longer); })
                .find(": expected an episode that runs " + std::to_string(longer.actions.size()) + " actions, got one "
                      "that ended after " + std::to_string(recorded_.actions.size()) + " (success held)"),
            std::string::npos);
  EXPECT_EQ(error_of([&] { replay_episode(specs_[1], recorded_); }),
            name + ": expected spec " + recorded_.spec_hash + ", got spec " + script::spec_hash(specs_[1]));
}

}  // namespace
}  // namespace hribench::io
