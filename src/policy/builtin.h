#pragma once
// Built-in policies that need nothing but the observation.
//   noop   — holds the robot where it is: zero deltas (ee_delta) or the observed joint
//            positions (joint_pos), and the observed gripper opening.
//   random — uniform actions inside ActionLimits, seeded: the same (seed, episode seed,
//            observations) give the same actions.
// Both size their actions and read the gripper's range from the episode's robot
// (EpisodeInfo::robot, model/robot.h); act() before reset() is a bug (HRIB_CHECK).

#include <cstdint>
#include <memory>

#include "core/rng.h"
#include "policy/policy.h"

namespace hribench::policy {

class NoopPolicy : public Policy {
 public:
  explicit NoopPolicy(ActionSpace space = ActionSpace::kEeDelta);
  PolicySpec spec() const override;
  void reset(const EpisodeInfo& info) override;
  ActionChunk act(const Observation& observation) override;

 private:
  ActionSpace space_;
  double max_width_ = 0;  // the robot's full gripper opening, m (set by reset)
};

class RandomPolicy : public Policy {
 public:
  // `scale` in (0, 1] shrinks the sampled range around the centre of the limits (ee_delta:
  // around zero; joint_pos: around the observed joint positions, clamped to the limits).
  // `limits` gives the ee_delta bounds; joint_pos uses the episode robot's joint limits.
  RandomPolicy(ActionSpace space, uint64_t seed, double scale, ActionLimits limits = {},
               int chunk_length = 1);
  PolicySpec spec() const override;
  // Restarts the stream from (seed, episode seed): episodes are independent of run order.
  void reset(const EpisodeInfo& info) override;
  ActionChunk act(const Observation& observation) override;

 private:
  ActionSpace space_;
  uint64_t seed_;
  double scale_;
  ActionLimits limits_;
  int chunk_length_;
  core::Rng rng_;
};

}  // namespace hribench::policy
