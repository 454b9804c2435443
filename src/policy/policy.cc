#include "policy/policy.h"

#include <cmath>
#include <fmt/format.h>

#include "core/errors.h"

namespace hribench::policy {

std::string_view to_string(ActionSpace space) {
  switch (space) {
    case ActionSpace::kEeDelta:
      return "ee_delta";
    case ActionSpace::kJointPos:
      return "joint_pos";
  }
  return "unknown";
}

ActionSpace action_space_from_string(std::string_view name, std::string_view where) {
  if (name == "ee_delta") return ActionSpace::kEeDelta;
  if (name == "joint_pos") return ActionSpace::kJointPos;
  throw core::InputError(std::string(where), "ee_delta or joint_pos", "'" + std::string(name) + "'");
}

int action_dim(ActionSpace space, size_t dof) {
  return space == ActionSpace::kEeDelta ? 7 : static_cast<int>(dof) + 1;
}

int action_dim(ActionSpace space, const model::Robot& robot) { return action_dim(space, robot.dof()); }

ActionLimits action_limits(const model::Robot& robot) {
  ActionLimits limits;
  limits.robot = robot.name;
  limits.q_min = robot.q_min();
  limits.q_max = robot.q_max();
  return limits;
}

std::string_view to_string(PolicyErrorKind kind) {
  switch (kind) {
    case PolicyErrorKind::kWrongSpace:
      return "wrong_space";
    case PolicyErrorKind::kEmptyChunk:
      return "empty_chunk";
    case PolicyErrorKind::kWrongShape:
      return "wrong_shape";
    case PolicyErrorKind::kNonFinite:
      return "non_finite";
    case PolicyErrorKind::kOutOfRange:
      return "out_of_range";
    case PolicyErrorKind::kFailed:
      return "failed";
  }
  return "unknown";
}

PolicyError::PolicyError(PolicyErrorKind kind, const std::string& message)
    : std::runtime_error(std::string(to_string(kind)) + ": " + message), kind_(kind) {}

namespace {

// The allowed interval of value `j` of an action in `space`.
std::pair<double, double> value_range(ActionSpace space, size_t j, const ActionLimits& limits) {
  const size_t gripper = static_cast<size_t>(action_dim(space, limits.q_min.size())) - 1;
  if (j == gripper) return {0.0, 1.0};
  if (space == ActionSpace::kJointPos) return {limits.q_min[j], limits.q_max[j]};
  const double bound = j < 3 ? limits.max_ee_translation : limits.max_ee_rotation;
  return {-bound, bound};
}

// What an action of `space` holds, for error messages.
std::string layout(ActionSpace space, const ActionLimits& limits) {
  if (space == ActionSpace::kEeDelta) return std::string(to_string(space));
  return fmt::format("joint_pos: {} joints of {} + gripper", limits.q_min.size(), limits.robot);
}

}  // namespace

void validate_chunk(const ActionChunk& chunk, ActionSpace expected, const ActionLimits& limits) {
  if (chunk.space != expected) {
    throw PolicyError(PolicyErrorKind::kWrongSpace,
                      fmt::format("expected {} actions, got {}", to_string(expected),
                                  to_string(chunk.space)));
  }
  if (chunk.actions.empty()) {
    throw PolicyError(PolicyErrorKind::kEmptyChunk, "the chunk holds no actions");
  }
  HRIB_CHECK(expected != ActionSpace::kJointPos || !limits.q_min.empty())
      << "joint_pos actions validated without the robot's joint limits (action_limits)";
  const size_t dim = static_cast<size_t>(action_dim(expected, limits.q_min.size()));
  for (size_t i = 0; i < chunk.actions.size(); ++i) {
    const Action& action = chunk.actions[i];
    if (action.size() != dim) {
      throw PolicyError(PolicyErrorKind::kWrongShape,
                        fmt::format("action {}: expected {} values ({}), got {}", i, dim,
                                    layout(expected, limits), action.size()));
    }
    for (size_t j = 0; j < dim; ++j) {
      if (!std::isfinite(action[j])) {
        throw PolicyError(PolicyErrorKind::kNonFinite,
                          fmt::format("action {} value {}: {}", i, j, action[j]));
      }
      const auto [lo, hi] = value_range(expected, j, limits);
      if (action[j] < lo || action[j] > hi) {
        throw PolicyError(PolicyErrorKind::kOutOfRange,
                          fmt::format("action {} value {}: {} is outside [{}, {}]", i, j,
                                      action[j], lo, hi));
      }
    }
  }
}

}  // namespace hribench::policy
