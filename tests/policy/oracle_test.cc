// The expert policy without physics: its declared needs, its errors, the registry names, and
// the first actions on hand-built observations (waiting for the cue, deterministic).

#include "policy/oracle.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "human/skeleton.h"
#include "policy/registry.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::policy {
namespace {

EpisodeInfo info_for(const std::string& file, uint64_t seed) {
  EpisodeInfo info;
  auto spec = std::make_shared<script::EpisodeSpec>(script::sample(script::load_scenario(file), seed));
  info.task = spec->task;
  info.instruction = spec->instruction;
  info.seed = seed;
  info.horizon = spec->horizon;
  info.episode = spec;
  return info;
}

// The robot at a home-like pose, every scene object at its sampled place.
Observation observation_for(const script::EpisodeSpec& spec, double time) {
  Observation obs;
  obs.time = time;
  obs.proprio.gripper_width = 0.08;
  obs.proprio.X_WT.translation = core::Vec3(0.55, 0, 1.27);
  obs.proprio.X_WT.rotation = core::axis_angle(core::Vec3::UnitX(), core::kPi);
  StateObservation state;
  for (const auto& entry : spec.scene.objects) {
    ObjectPose pose{entry.name, core::Pose::Identity()};
    if (entry.value.pose) {
      pose.X_WO.translation = core::Vec3(entry.value.pose->xy[0].value(), entry.value.pose->xy[1].value(), 0.75);
    }
    state.objects.push_back(pose);
  }
  for (size_t j = 0; j < state.human_joints_W.size(); ++j) state.human_joints_W[j] = core::Vec3(1.3, 0, 1.0);
  obs.state = state;
  return obs;
}

TEST(ExpertPolicy, DeclaresThePrivilegedStateTrackInEeDelta) {
  for (const char* name : {"oracle", "reactive", "blind"}) {
    const std::unique_ptr<Policy> policy = make_policy(name);
    const PolicySpec spec = policy->spec();
    EXPECT_TRUE(spec.privileged) << name;
    EXPECT_TRUE(spec.state_track) << name;
    EXPECT_TRUE(spec.cameras.empty()) << name;
    EXPECT_EQ(spec.action_space, ActionSpace::kEeDelta) << name;
  }
  EXPECT_THROW(make_policy("oracle?speed=2"), core::InputError);
}

TEST(ExpertPolicy, ResetWithoutTheEpisodeIsAPolicyError) {
  ExpertPolicy oracle(Competence::kOracle);
  try {
    oracle.reset(EpisodeInfo{});
    FAIL() << "expected a PolicyError";
  } catch (const PolicyError& e) {
    EXPECT_EQ(e.kind(), PolicyErrorKind::kFailed);
    EXPECT_STREQ(e.what(), "failed: oracle: needs the privileged episode");
  }
}

// I1 before the stroke: the oracle holds still (zero translation), blind already moves; the
// actions are valid ee_delta actions and the same for the same observations.
TEST(ExpertPolicy, WaitsForTheCueUnlessBlindAndIsDeterministic) {
  const EpisodeInfo info = info_for("tasks/I1_point_pick.yaml", 0);
  const Observation obs = observation_for(*info.episode, 0.05);
  ExpertPolicy oracle(Competence::kOracle);
  oracle.reset(info);
  const ActionChunk first = oracle.act(obs);
  validate_chunk(first, ActionSpace::kEeDelta, ActionLimits{});
  EXPECT_DOUBLE_EQ(first.actions[0][0], 0.0);
  EXPECT_DOUBLE_EQ(first.actions[0][1], 0.0);
  EXPECT_DOUBLE_EQ(first.actions[0][2], 0.0);
  EXPECT_EQ(oracle.current_step(), 0u);

  ExpertPolicy blind(Competence::kBlind);
  blind.reset(info);
  ActionChunk moving;
  for (int k = 1; k <= 5; ++k) moving = blind.act(observation_for(*info.episode, 0.05 * k));
  validate_chunk(moving, ActionSpace::kEeDelta, ActionLimits{});
  const core::Vec3 d(moving.actions[0][0], moving.actions[0][1], moving.actions[0][2]);
  EXPECT_GT(d.norm(), 1e-3);

  ExpertPolicy again(Competence::kBlind);
  again.reset(info);
  ActionChunk repeat;
  for (int k = 1; k <= 5; ++k) repeat = again.act(observation_for(*info.episode, 0.05 * k));
  EXPECT_EQ(repeat.actions, moving.actions);
}

// X1 while the intrusion runs: the oracle waits beside the intruding hand, moving sideways away
// from its palm (here toward +y, away from the cube it was sent for at y < -0.2); the palm on the
// other side sends it the other way.
TEST(ExpertPolicy, YieldsSidewaysAwayFromTheIntrudingPalm) {
  const EpisodeInfo info = info_for("tasks/X1_intrusion_yield.yaml", 0);
  const auto sideways = [&](double palm_y) {
    ExpertPolicy oracle(Competence::kOracle);
    oracle.reset(info);
    Observation obs = observation_for(*info.episode, 0.05);
    obs.proprio.X_WT.translation = core::Vec3(0.30, -0.05, 1.05);
    // The right forearm reaching in: palm 8 cm beyond the wrist, at (0.62, palm_y, 0.95).
    obs.state->human_joints_W[static_cast<size_t>(human::index(human::Joint::kRightElbow))] =
        core::Vec3(0.90, palm_y, 0.95);
    obs.state->human_joints_W[static_cast<size_t>(human::index(human::Joint::kRightWrist))] =
        core::Vec3(0.70, palm_y, 0.95);
    obs.events.push_back(ScriptEvent{0.0, "act_start", "intrude.start", ""});
    double dy = 0;
    for (int k = 1; k <= 8; ++k) {
      obs.time = 0.05 * k;
      const ActionChunk chunk = oracle.act(obs);
      validate_chunk(chunk, ActionSpace::kEeDelta, ActionLimits{});
      dy += chunk.actions[0][1];
    }
    return dy;
  };
  EXPECT_GT(sideways(-0.10), 1e-3);
  EXPECT_LT(sideways(0.10), -1e-3);
}

}  // namespace
}  // namespace hribench::policy
