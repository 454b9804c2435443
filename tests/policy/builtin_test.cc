#include "policy/builtin.h"

#include <gtest/gtest.h>

#include "core/errors.h"

namespace hribench::policy {
namespace {

Observation observation_at(double t) {
  Observation obs;
  obs.time = t;
  obs.proprio.joint_pos = {0.1, -0.3, 0.0, -2.0, 0.0, 1.8, 0.7};
  obs.proprio.gripper_width = 0.04;
  return obs;
}

TEST(NoopPolicy, HoldsTheRobot) {
  NoopPolicy ee(ActionSpace::kEeDelta);
  ee.reset(EpisodeInfo{});
  const ActionChunk a = ee.act(observation_at(0));
  ASSERT_EQ(a.actions.size(), 1u);
  EXPECT_EQ(a.actions[0], (Action{0, 0, 0, 0, 0, 0, 0.5}));
  NoopPolicy joints(ActionSpace::kJointPos);
  joints.reset(EpisodeInfo{});
  const ActionChunk b = joints.act(observation_at(0));
  EXPECT_EQ(b.actions[0], (Action{0.1, -0.3, 0.0, -2.0, 0.0, 1.8, 0.7, 0.5}));
  EXPECT_NO_THROW(validate_chunk(b, ActionSpace::kJointPos, action_limits(model::panda())));
  EXPECT_FALSE(joints.spec().state_track);
  EXPECT_TRUE(joints.spec().cameras.empty());
}

TEST(RandomPolicy, SeededDeterministicAndValid) {
  RandomPolicy p(ActionSpace::kJointPos, 7, 0.5, ActionLimits{}, 4);
  RandomPolicy q(ActionSpace::kJointPos, 7, 0.5, ActionLimits{}, 4);
  EpisodeInfo info;
  info.seed = 11;
  p.reset(info);
  q.reset(info);
  const ActionChunk a = p.act(observation_at(0));
  EXPECT_EQ(a.actions.size(), 4u);
  EXPECT_EQ(a.actions, q.act(observation_at(0)).actions);
  EXPECT_NO_THROW(validate_chunk(a, ActionSpace::kJointPos, action_limits(model::panda())));
  // Reset restarts the stream; another episode seed gives other actions.
  p.reset(info);
  EXPECT_EQ(p.act(observation_at(0)).actions, a.actions);
  info.seed = 12;
  p.reset(info);
  EXPECT_NE(p.act(observation_at(0)).actions, a.actions);
}

TEST(NoopPolicy, UnknownRobotIsAnInputError) {
  NoopPolicy noop(ActionSpace::kJointPos);
  EpisodeInfo info;
  info.robot = "so101";
  try {
    noop.reset(info);
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "robot: expected one of panda, got 'so101'");
  }
}

TEST(RandomPolicy, JointPosSizedAndBoundedByTheEpisodeRobot) {
  RandomPolicy p(ActionSpace::kJointPos, 3, 1.0);
  p.reset(EpisodeInfo{});
  const model::Robot& panda = model::panda();
  for (int i = 0; i < 20; ++i) {
    const Action a = p.act(observation_at(0.05 * i)).actions[0];
    ASSERT_EQ(a.size(), panda.dof() + 1);
    for (size_t j = 0; j < panda.dof(); ++j) {
      EXPECT_GE(a[j], panda.joints[j].q_min);
      EXPECT_LE(a[j], panda.joints[j].q_max);
    }
  }
}

TEST(RandomPolicy, EeDeltaWithinScaledLimits) {
  RandomPolicy p(ActionSpace::kEeDelta, 1, 0.5);
  p.reset(EpisodeInfo{});
  for (int i = 0; i < 50; ++i) {
    const ActionChunk a = p.act(observation_at(0.05 * i));
    for (size_t j = 0; j < 3; ++j) EXPECT_LE(std::abs(a.actions[0][j]), 0.025);
    EXPECT_NO_THROW(validate_chunk(a, ActionSpace::kEeDelta, ActionLimits{}));
  }
}

TEST(RandomPolicy, RejectsBadOptions) {
  try {
    RandomPolicy(ActionSpace::kEeDelta, 1, 0.0);
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "policy random: scale: expected a number in (0, 1], got 0.000000");
  }
  EXPECT_THROW(RandomPolicy(ActionSpace::kEeDelta, 1, 1.0, ActionLimits{}, 0), core::InputError);
}

TEST(CameraRequests, ParsesNamesAndSizes) {
  EXPECT_TRUE(parse_camera_requests("", "cameras").empty());
  const std::vector<CameraRequest> two = parse_camera_requests("agentview:224x224+wrist:128x96", "cameras");
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].name, "agentview");
  EXPECT_EQ(two[0].width, 224);
  EXPECT_EQ(two[0].height, 224);
  EXPECT_EQ(two[1].name, "wrist");
  EXPECT_EQ(two[1].width, 128);
  EXPECT_EQ(two[1].height, 96);
}

TEST(CameraRequests, BadRequestsNameThePart) {
  const std::string expected =
      "policy noop: cameras: expected NAME:WIDTHxHEIGHT joined by '+' (e.g. "
      "agentview:224x224+wrist:224x224), sides in [1, 4096], got ";
  for (const auto& [text, part] : {std::pair<std::string, std::string>{"agentview", "'agentview'"},
                                   {"agentview:224", "'agentview:224'"},
                                   {":224x224", "':224x224'"},
                                   {"agentview:0x224", "'agentview:0x224'"},
                                   {"agentview:224x5000", "'agentview:224x5000'"},
                                   {"agentview:22.5x224", "'agentview:22.5x224'"},
                                   {"agentview:224x224+wrist", "'wrist'"}}) {
    try {
      parse_camera_requests(text, "policy noop: cameras");
      ADD_FAILURE() << text;
    } catch (const core::InputError& e) {
      EXPECT_EQ(std::string(e.what()), expected + part) << text;
    }
  }
  try {
    parse_camera_requests("wrist:64x64+wrist:32x32", "policy random: cameras");
    ADD_FAILURE();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "policy random: cameras: expected each camera once, got 'wrist' twice");
  }
}

TEST(CameraRequests, NoopAndRandomAskForThem) {
  const std::vector<CameraRequest> cameras = parse_camera_requests("agentview:32x24", "cameras");
  const PolicySpec noop = NoopPolicy(ActionSpace::kEeDelta, cameras).spec();
  ASSERT_EQ(noop.cameras.size(), 1u);
  EXPECT_EQ(noop.cameras[0].name, "agentview");
  EXPECT_EQ(noop.cameras[0].width, 32);
  EXPECT_EQ(noop.cameras[0].height, 24);
  const PolicySpec random = RandomPolicy(ActionSpace::kEeDelta, 1, 1.0, ActionLimits{}, 1, cameras).spec();
  ASSERT_EQ(random.cameras.size(), 1u);
  EXPECT_EQ(random.cameras[0].name, "agentview");
}

}  // namespace
}  // namespace hribench::policy
