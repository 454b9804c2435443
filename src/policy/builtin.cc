#include "policy/builtin.h"

#include <algorithm>

#include "core/errors.h"

namespace hribench::policy {
namespace {

// The observed opening as a gripper command (a fraction of the full opening).
double gripper_command(const Proprioception& proprio, double max_width) {
  return std::clamp(proprio.gripper_width / max_width, 0.0, 1.0);
}

}  // namespace

NoopPolicy::NoopPolicy(ActionSpace space) : space_(space) {}

PolicySpec NoopPolicy::spec() const { return PolicySpec{{}, false, space_, 1}; }

void NoopPolicy::reset(const EpisodeInfo& info) {
  max_width_ = model::robot_by_name(info.robot).gripper.max_width();
}

ActionChunk NoopPolicy::act(const Observation& observation) {
  HRIB_CHECK(max_width_ > 0) << "noop: act before reset";
  Action action(static_cast<size_t>(action_dim(space_, observation.proprio.joint_pos.size())), 0.0);
  // Hold: zero deltas, or the observed joint positions; keep the gripper as it is.
  if (space_ == ActionSpace::kJointPos) {
    std::copy(observation.proprio.joint_pos.begin(), observation.proprio.joint_pos.end(),
              action.begin());
  }
  action.back() = gripper_command(observation.proprio, max_width_);
  return ActionChunk{space_, {std::move(action)}};
}

RandomPolicy::RandomPolicy(ActionSpace space, uint64_t seed, double scale, ActionLimits limits,
                           int chunk_length)
    : space_(space),
      seed_(seed),
      scale_(scale),
      limits_(limits),
      chunk_length_(chunk_length),
      rng_(seed) {
  if (!(scale > 0 && scale <= 1)) {
    throw core::InputError("policy random: scale", "a number in (0, 1]", std::to_string(scale));
  }
  if (chunk_length < 1) {
    throw core::InputError("policy random: chunk", "an integer >= 1",
                           std::to_string(chunk_length));
  }
}

PolicySpec RandomPolicy::spec() const { return PolicySpec{{}, false, space_, chunk_length_}; }

void RandomPolicy::reset(const EpisodeInfo& info) {
  rng_ = core::Rng(seed_).split(info.seed);
  const ActionLimits robot = action_limits(model::robot_by_name(info.robot));
  limits_.robot = robot.robot;
  limits_.q_min = robot.q_min;
  limits_.q_max = robot.q_max;
}

ActionChunk RandomPolicy::act(const Observation& observation) {
  HRIB_CHECK(!limits_.q_min.empty()) << "random: act before reset";
  ActionChunk chunk{space_, {}};
  for (int k = 0; k < chunk_length_; ++k) {
    Action action(static_cast<size_t>(action_dim(space_, limits_.q_min.size())), 0.0);
    for (size_t j = 0; j + 1 < action.size(); ++j) {
      if (space_ == ActionSpace::kEeDelta) {
        const double bound = scale_ * (j < 3 ? limits_.max_ee_translation : limits_.max_ee_rotation);
        action[j] = rng_.uniform(-bound, bound);
      } else {
        // Around the observed position, inside the joint limits.
        const double half = 0.5 * scale_ * (limits_.q_max[j] - limits_.q_min[j]);
        const double lo = std::max(limits_.q_min[j], observation.proprio.joint_pos[j] - half);
        const double hi = std::min(limits_.q_max[j], observation.proprio.joint_pos[j] + half);
        action[j] = lo < hi ? rng_.uniform(lo, hi) : limits_.q_min[j];
      }
    }
    action.back() = rng_.uniform();
    chunk.actions.push_back(std::move(action));
  }
  return chunk;
}

}  // namespace hribench::policy
