#pragma once
// Built-in policies that need nothing but the observation.
//   noop   — holds the robot where it is: zero deltas (ee_delta) or the observed joint
//            positions (joint_pos), and the observed gripper opening.
//   random — uniform actions inside ActionLimits, seeded: the same (seed, episode seed,
//            observations) give the same actions.
// Both size their actions and read the gripper's range from the episode's robot
// (EpisodeInfo::robot, model/robot.h); act() before reset() is a bug (HRIB_CHECK).
// Both can ask for camera images they do not look at (the cameras= option,
// parse_camera_requests), so that an episode's rendering cost can be measured with them.

#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "core/rng.h"
#include "policy/policy.h"

namespace hribench::policy {

// Camera requests written NAME:WIDTHxHEIGHT, several joined by '+' (a policy list on the
// command line is comma-separated), e.g. "agentview:224x224+wrist:224x224"; "" is none.
// Sides in [1, render::kMaxImageSide]; a camera named twice is refused. Throws
// core::InputError (where `where`) naming what was expected and the part that is not. Camera
// names are checked against the episode's model when the episode starts.
std::vector<CameraRequest> parse_camera_requests(std::string_view text, std::string_view where);

class NoopPolicy : public Policy {
 public:
  explicit NoopPolicy(ActionSpace space = ActionSpace::kEeDelta,
                      std::vector<CameraRequest> cameras = {});
  PolicySpec spec() const override;
  void reset(const EpisodeInfo& info) override;
  ActionChunk act(const Observation& observation) override;

 private:
  ActionSpace space_;
  std::vector<CameraRequest> cameras_;
  double max_width_ = 0;  // the robot's full gripper opening, m (set by reset)
};

class RandomPolicy : public Policy {
 public:
  // `scale` in (0, 1] shrinks the sampled range around the centre of the limits (ee_delta:
  // around zero; joint_pos: around the observed joint positions, clamped to the limits).
  // `limits` gives the ee_delta bounds; joint_pos uses the episode robot's joint limits.
  RandomPolicy(ActionSpace space, uint64_t seed, double scale, ActionLimits limits = {},
               int chunk_length = 1, std::vector<CameraRequest> cameras = {});
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
  std::vector<CameraRequest> cameras_;
  core::Rng rng_;
};

}  // namespace hribench::policy
