// The expert policy without physics: its declared needs, its errors, the registry names, and
// the first actions on hand-built observations (waiting for the cue, deterministic).

#include "policy/oracle.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "human/skeleton.h"
#include "policy/oracle_internal.h"
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

// I3 before the "your turn" cue: a demonstrator's head leaning in within kSlowDistance of the
// waiting hand makes the oracle back off, up and away from bottle B (moving toward B would be
// the start of `imitate`, premature); with the head far away it holds still. A stop cue (I4)
// would hold it still whatever the distance (the `still` constraint).
TEST(ExpertPolicy, WaitingForTheCueItBacksAwayFromAHeadLeaningInButNeverTowardItsObject) {
  const EpisodeInfo info = info_for("tasks/I3_demo_imitate.yaml", 0);
  const auto motion = [&](const core::Vec3& head) {
    ExpertPolicy oracle(Competence::kOracle);
    oracle.reset(info);
    Observation obs = observation_for(*info.episode, 0.05);
    for (const human::Joint j : {human::Joint::kHead, human::Joint::kNeck}) {
      obs.state->human_joints_W[static_cast<size_t>(human::index(j))] = head;
    }
    core::Vec3 moved = core::Vec3::Zero();
    for (int k = 1; k <= 10; ++k) {
      obs.time = 0.05 * k;
      const ActionChunk chunk = oracle.act(obs);
      validate_chunk(chunk, ActionSpace::kEeDelta, ActionLimits{});
      moved += core::Vec3(chunk.actions[0][0], chunk.actions[0][1], chunk.actions[0][2]);
    }
    return moved;
  };
  EXPECT_NEAR(motion(core::Vec3(1.3, 0, 1.4)).norm(), 0.0, 1e-12);
  const core::Vec3 away = motion(core::Vec3(0.85, 0, 1.35));
  EXPECT_GT(away.norm(), 0.02);
  EXPECT_LT(away.x(), 0.0);  // back, away from the head
  const ObjectPose* b = nullptr;
  const Observation obs = observation_for(*info.episode, 0.05);
  for (const ObjectPose& o : obs.state->objects) {
    if (o.name == "inst_b") b = &o;
  }
  ASSERT_NE(b, nullptr);
  const core::Vec3 to_b = b->X_WO.translation - obs.proprio.X_WT.translation;
  EXPECT_LT(away.dot(to_b.normalized()), 0.0);
}

// Recovery (X2): a bottle the person put down on its side is recognised as lying and grasped
// across the middle of its body; one leaning less than 60 deg, or a cube, is not.
TEST(ExpertPolicy, AKnockedOverBottleIsGraspedAcrossItsLyingBody) {
  using oracle_internal::lying;
  core::Pose X_WO = core::Pose::Identity();
  X_WO.translation = core::Vec3(0.6, 0.2, 0.75);
  EXPECT_FALSE(lying("bottle", X_WO));
  X_WO.rotation = core::axis_angle(core::Vec3::UnitY(), 0.9);  // 52 deg
  EXPECT_FALSE(lying("bottle", X_WO));
  X_WO.rotation = core::axis_angle(core::Vec3::UnitY(), core::kPi / 2);  // axis along +x
  EXPECT_TRUE(lying("bottle", X_WO));
  EXPECT_TRUE(lying("cup", X_WO));
  EXPECT_FALSE(lying("cube", X_WO));
  const core::Vec3 grasp = oracle_internal::lying_grasp(X_WO, core::Vec3(0.032, 0.032, 0.105));
  EXPECT_NEAR(grasp.x(), 0.6 + 2 * oracle_internal::kLyingGraspAlong * 0.105, 1e-12);
  EXPECT_NEAR(grasp.y(), 0.2, 1e-12);
  EXPECT_NEAR(grasp.z(), 0.75, 1e-12);
  // Finger yaws are taken modulo a half turn (the gripper is symmetric).
  EXPECT_NEAR(oracle_internal::wrap_half_turn(0.75 * core::kPi), -0.25 * core::kPi, 1e-12);
  EXPECT_NEAR(oracle_internal::wrap_half_turn(-0.5 * core::kPi), -0.5 * core::kPi, 1e-12);
  EXPECT_NEAR(oracle_internal::wrap_half_turn(0.3), 0.3, 1e-12);
}

// The oracle's clearance estimate: the smallest axis distance minus both radii over every pair,
// with `away` from the body's nearest point toward the robot's; `away` is kept where the axes
// touch.
TEST(ExpertPolicy, SurfaceGapIsTheNearestPairsAxisDistanceLessBothRadii) {
  using core::Vec3;
  using oracle_internal::GapCapsule;
  const std::array<GapCapsule, 2> robot = {GapCapsule{Vec3(0, 0, 1.0), Vec3(0, 0, 1.2), 0.05},
                                           GapCapsule{Vec3(0, 0, 2.0), Vec3(0, 0, 2.2), 0.05}};
  const std::array<GapCapsule, 2> body = {GapCapsule{Vec3(0.5, -1, 1.1), Vec3(0.5, 1, 1.1), 0.1},
                                          GapCapsule{Vec3(3, 0, 0), Vec3(3, 0, 0), 0.2}};
  Vec3 away(0, 0, 1);
  EXPECT_NEAR(oracle_internal::surface_gap(robot, body, away), 0.5 - 0.05 - 0.1, 1e-12);
  EXPECT_NEAR((away - Vec3(-1, 0, 0)).norm(), 0, 1e-12);
  // Crossing axes: overlapping (negative gap), the direction kept.
  const std::array<GapCapsule, 1> crossing = {GapCapsule{Vec3(-1, 0, 1.1), Vec3(1, 0, 1.1), 0.1}};
  away = Vec3(0, 1, 0);
  EXPECT_NEAR(oracle_internal::surface_gap(robot, crossing, away), -0.15, 1e-12);
  EXPECT_NEAR((away - Vec3(0, 1, 0)).norm(), 0, 1e-12);
}

}  // namespace
}  // namespace hribench::policy
