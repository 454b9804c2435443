#pragma once
// Built-in policies that need nothing but the observation.
//   noop   — holds the robot where it is: zero deltas (ee_delta) or the observed joint
//            positions (joint_pos), and the observed gripper opening.
//   random — uniform actions inside ActionLimits, seeded: the same (seed, episode seed,
//            observations) give the same actions.

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
};

class RandomPolicy : public Policy {
 public:
  // `scale` in (0, 1] shrinks the sampled range around the centre of the limits (ee_delta:
  // around zero; joint_pos: around the observed joint positions, clamped to the limits).
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
