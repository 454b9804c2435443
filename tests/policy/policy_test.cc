#include "policy/policy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/errors.h"

namespace hribench::policy {
namespace {

ActionChunk one(ActionSpace space, Action action) { return ActionChunk{space, {std::move(action)}}; }

PolicyErrorKind error_kind(const ActionChunk& chunk, ActionSpace space, std::string* message) {
  try {
    validate_chunk(chunk, space, action_limits(model::panda()));
  } catch (const PolicyError& e) {
    *message = e.what();
    return e.kind();
  }
  ADD_FAILURE() << "no PolicyError";
  return PolicyErrorKind::kFailed;
}

TEST(ActionSpace, NamesAndDims) {
  EXPECT_EQ(to_string(ActionSpace::kEeDelta), "ee_delta");
  EXPECT_EQ(action_space_from_string("joint_pos", "x"), ActionSpace::kJointPos);
  EXPECT_EQ(action_dim(ActionSpace::kEeDelta, model::panda()), 7);
  EXPECT_EQ(action_dim(ActionSpace::kJointPos, model::panda()), 8);
  // Sized by the robot's dof: a 5-joint arm takes 6 values in joint_pos, still 7 in ee_delta.
  EXPECT_EQ(action_dim(ActionSpace::kJointPos, 5), 6);
  EXPECT_EQ(action_dim(ActionSpace::kEeDelta, 5), 7);
  try {
    action_space_from_string("cartesian", "policy noop: space");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "policy noop: space: expected ee_delta or joint_pos, got 'cartesian'");
  }
}

TEST(ValidateChunk, AcceptsWellFormedChunks) {
  EXPECT_NO_THROW(validate_chunk(one(ActionSpace::kEeDelta, {0.05, -0.05, 0, 0.25, 0, -0.25, 1}),
                                 ActionSpace::kEeDelta, ActionLimits{}));
  ActionChunk chunk{ActionSpace::kJointPos, {}};
  for (int i = 0; i < 10; ++i) chunk.actions.push_back({0, 0, 0, -1.5, 0, 1.5, 0.7, 0.0});
  EXPECT_NO_THROW(validate_chunk(chunk, ActionSpace::kJointPos, action_limits(model::panda())));
}

TEST(ActionLimits, DerivedFromTheRobotDescription) {
  const model::Robot& panda = model::panda();
  const ActionLimits limits = action_limits(panda);
  EXPECT_EQ(limits.robot, "panda");
  ASSERT_EQ(limits.q_min.size(), panda.dof());
  for (size_t i = 0; i < panda.dof(); ++i) {
    EXPECT_EQ(limits.q_min[i], panda.joints[i].q_min);
    EXPECT_EQ(limits.q_max[i], panda.joints[i].q_max);
  }
  // The ee_delta bounds are the benchmark's, whatever the robot.
  EXPECT_EQ(limits.max_ee_translation, ActionLimits{}.max_ee_translation);
  EXPECT_EQ(limits.max_ee_rotation, ActionLimits{}.max_ee_rotation);
  // Another robot: its own dof and limits size and bound joint_pos actions.
  model::Robot arm = panda;
  arm.name = "five";
  arm.joints.resize(5);
  const ActionLimits five = action_limits(arm);
  EXPECT_NO_THROW(validate_chunk(ActionChunk{ActionSpace::kJointPos, {{0, 0, 0, -1, 0, 0.5}}},
                                 ActionSpace::kJointPos, five));
  try {
    validate_chunk(ActionChunk{ActionSpace::kJointPos, {{0, 0, 0, -1, 0, 0, 0.5}}},
                   ActionSpace::kJointPos, five);
    FAIL();
  } catch (const PolicyError& e) {
    EXPECT_STREQ(e.what(), "wrong_shape: action 0: expected 6 values (joint_pos: 5 joints of five + gripper), got 7");
  }
}

TEST(ValidateChunk, TypedErrorsWithMessages) {
  std::string msg;
  EXPECT_EQ(error_kind(one(ActionSpace::kJointPos, {0, 0, 0, -1, 0, 1, 0, 0}),
                       ActionSpace::kEeDelta, &msg),
            PolicyErrorKind::kWrongSpace);
  EXPECT_EQ(msg, "wrong_space: expected ee_delta actions, got joint_pos");
  EXPECT_EQ(error_kind(ActionChunk{ActionSpace::kEeDelta, {}}, ActionSpace::kEeDelta, &msg),
            PolicyErrorKind::kEmptyChunk);
  EXPECT_EQ(error_kind(one(ActionSpace::kEeDelta, {0, 0, 0, 0, 0, 0}), ActionSpace::kEeDelta, &msg),
            PolicyErrorKind::kWrongShape);
  EXPECT_EQ(msg, "wrong_shape: action 0: expected 7 values (ee_delta), got 6");
  EXPECT_EQ(error_kind(one(ActionSpace::kJointPos, {0, 0, 0, -1, 0, 1, 0}), ActionSpace::kJointPos, &msg),
            PolicyErrorKind::kWrongShape);
  EXPECT_EQ(msg, "wrong_shape: action 0: expected 8 values (joint_pos: 7 joints of panda + gripper), got 7");
  EXPECT_EQ(error_kind(one(ActionSpace::kEeDelta,
                           {0, std::numeric_limits<double>::quiet_NaN(), 0, 0, 0, 0, 0}),
                       ActionSpace::kEeDelta, &msg),
            PolicyErrorKind::kNonFinite);
  EXPECT_EQ(msg, "non_finite: action 0 value 1: nan");
  EXPECT_EQ(error_kind(one(ActionSpace::kEeDelta, {0.06, 0, 0, 0, 0, 0, 0}), ActionSpace::kEeDelta,
                       &msg),
            PolicyErrorKind::kOutOfRange);
  EXPECT_EQ(msg, "out_of_range: action 0 value 0: 0.06 is outside [-0.05, 0.05]");
  // Gripper outside [0, 1]; joint 4 above its limit.
  EXPECT_EQ(error_kind(one(ActionSpace::kEeDelta, {0, 0, 0, 0, 0, 0, 1.5}), ActionSpace::kEeDelta,
                       &msg),
            PolicyErrorKind::kOutOfRange);
  EXPECT_EQ(error_kind(one(ActionSpace::kJointPos, {0, 0, 0, 0.1, 0, 1, 0, 0}),
                       ActionSpace::kJointPos, &msg),
            PolicyErrorKind::kOutOfRange);
  EXPECT_EQ(msg, "out_of_range: action 0 value 3: 0.1 is outside [-3.0718, -0.0698]");
}

TEST(ValidateChunk, NamesTheBadActionInALongChunk) {
  ActionChunk chunk{ActionSpace::kEeDelta, {}};
  for (int i = 0; i < 5; ++i) chunk.actions.push_back({0, 0, 0, 0, 0, 0, 0.5});
  chunk.actions[3][6] = std::numeric_limits<double>::infinity();
  std::string msg;
  EXPECT_EQ(error_kind(chunk, ActionSpace::kEeDelta, &msg), PolicyErrorKind::kNonFinite);
  EXPECT_EQ(msg, "non_finite: action 3 value 6: inf");
}

}  // namespace
}  // namespace hribench::policy
