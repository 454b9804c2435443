#include "policy/builtin.h"

#include <algorithm>
#include <charconv>
#include <string>

#include "core/errors.h"
#include "render/renderer.h"

namespace hribench::policy {
namespace {

// The observed opening as a gripper command (a fraction of the full opening).
double gripper_command(const Proprioception& proprio, double max_width) {
  return std::clamp(proprio.gripper_width / max_width, 0.0, 1.0);
}

// A side of NAME:WIDTHxHEIGHT: decimal digits only, in [1, kMaxImageSide]; else -1.
int image_side(std::string_view digits) {
  int value = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (digits.empty() || error != std::errc() || end != digits.data() + digits.size() || value < 1 ||
      value > render::kMaxImageSide) {
    return -1;
  }
  return value;
}

}  // namespace

std::vector<CameraRequest> parse_camera_requests(std::string_view text, std::string_view where) {
  std::vector<CameraRequest> cameras;
  while (!text.empty()) {
    const size_t plus = text.find('+');
    const std::string_view item = text.substr(0, plus);
    text = plus == std::string_view::npos ? std::string_view() : text.substr(plus + 1);
    const size_t colon = item.find(':');
    const size_t x = item.find('x', colon == std::string_view::npos ? 0 : colon);
    CameraRequest request;
    if (colon != std::string_view::npos && colon > 0 && x != std::string_view::npos) {
      request.name = std::string(item.substr(0, colon));
      request.width = image_side(item.substr(colon + 1, x - colon - 1));
      request.height = image_side(item.substr(x + 1));
    }
    if (request.name.empty() || request.width < 0 || request.height < 0) {
      throw core::InputError(std::string(where),
                             "NAME:WIDTHxHEIGHT joined by '+' (e.g. agentview:224x224+wrist:224x224), sides in [1, " +
                                 std::to_string(render::kMaxImageSide) + "]",
                             "'" + std::string(item) + "'");
    }
    for (const CameraRequest& other : cameras) {
      if (other.name == request.name) {
        throw core::InputError(std::string(where), "each camera once", "'" + request.name + "' twice");
      }
    }
    cameras.push_back(std::move(request));
  }
  return cameras;
}

NoopPolicy::NoopPolicy(ActionSpace space, std::vector<CameraRequest> cameras)
    : space_(space), cameras_(std::move(cameras)) {}

PolicySpec NoopPolicy::spec() const { return PolicySpec{cameras_, false, space_, 1}; }

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
                           int chunk_length, std::vector<CameraRequest> cameras)
    : space_(space),
      seed_(seed),
      scale_(scale),
      limits_(limits),
      chunk_length_(chunk_length),
      cameras_(std::move(cameras)),
      rng_(seed) {
  if (!(scale > 0 && scale <= 1)) {
    throw core::InputError("policy random: scale", "a number in (0, 1]", std::to_string(scale));
  }
  if (chunk_length < 1) {
    throw core::InputError("policy random: chunk", "an integer >= 1",
                           std::to_string(chunk_length));
  }
}

PolicySpec RandomPolicy::spec() const { return PolicySpec{cameras_, false, space_, chunk_length_}; }

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
