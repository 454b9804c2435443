#include "eval/runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <optional>
#include <fmt/format.h>
#include <vector>

#include "core/errors.h"

namespace hribench::eval {

Latency parse_latency(std::string_view text) {
  if (text == "none") return {LatencyMode::kNone, 0};
  if (text == "measured") return {LatencyMode::kMeasured, 0};
  if (text.substr(0, 6) == "fixed:") {
    // A finite delay of at most a minute (longer is no interaction, and would overflow the
    // control-step count).
    const std::string ms(text.substr(6));
    char* end = nullptr;
    const double value = std::strtod(ms.c_str(), &end);
    if (ms.empty() || end != ms.c_str() + ms.size() || !std::isfinite(value) || value < 0 ||
        value > kMaxFixedLatencyMs) {
      throw core::InputError("--latency",
                             fmt::format("fixed:MS with MS milliseconds in [0, {}]", kMaxFixedLatencyMs),
                             "'" + std::string(text) + "'");
    }
    return {LatencyMode::kFixed, value / 1000.0};
  }
  throw core::InputError("--latency", "none, fixed:MS (milliseconds >= 0) or measured",
                         "'" + std::string(text) + "'");
}

std::string to_string(const Latency& latency) {
  switch (latency.mode) {
    case LatencyMode::kNone:
      return "none";
    case LatencyMode::kFixed:
      return fmt::format("fixed:{}", latency.fixed_seconds * 1000.0);
    case LatencyMode::kMeasured:
      return "measured";
  }
  return "unknown";
}

const EpisodeLog& run_episode(Episode& episode, policy::Policy& policy,
                              const std::function<bool(const Episode&)>& until) {
  const policy::PolicySpec spec = policy.spec();
  const policy::PolicySpec& observed = episode.policy_spec();
  if (spec.action_space != observed.action_space || spec.state_track != observed.state_track ||
      spec.privileged != observed.privileged || spec.cameras.size() != observed.cameras.size()) {
    throw core::InputError("run_episode", "an Episode made for the policy's spec (policy.spec())",
                           "an Episode of another observation or action space");
  }
  const RunOptions& options = episode.options();
  episode.reset();
  try {
    policy.reset(episode.info());
  } catch (const std::exception& ex) {
    episode.end(core::EpisodeStatus::kPolicyError, std::string("reset: ") + ex.what());
    return episode.log();
  }
  const auto stop = [&] { return until && until(episode); };
  std::deque<policy::Action> queue;     // actions to execute, one per control step
  std::vector<policy::Action> pending;  // a chunk that arrives when thinking ends
  std::vector<policy::Action> pending_rest;  // its actions after the first replan_every
  std::deque<policy::Action> rest;  // the current chunk's, executed while the next is thought of
  int thinking = 0;                     // control steps left until `pending` arrives
  while (!episode.done() && !stop()) {
    // Ask the policy when nothing is queued or on the way.
    if (queue.empty() && thinking == 0) {
      const policy::Observation obs = episode.observe();
      policy::ActionChunk chunk;
      const auto start = std::chrono::steady_clock::now();
      try {
        chunk = policy.act(obs);
        policy::validate_chunk(chunk, spec.action_space, episode.action_limits());
      } catch (const std::exception& ex) {
        episode.end(core::EpisodeStatus::kPolicyError, ex.what());
        break;
      }
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double delay = options.latency.mode == LatencyMode::kNone    ? 0.0
                           : options.latency.mode == LatencyMode::kFixed ? options.latency.fixed_seconds
                                                                         : wall;
      const size_t take = std::min(chunk.actions.size(), static_cast<size_t>(std::max(1, spec.replan_every)));
      std::vector<policy::Action> chunk_rest;
      if (spec.execute_while_thinking) chunk_rest.assign(chunk.actions.begin() + static_cast<long>(take), chunk.actions.end());
      chunk.actions.resize(take);
      thinking = static_cast<int>(std::ceil(delay / options.control_dt - 1e-9));
      if (thinking == 0) {
        queue.assign(chunk.actions.begin(), chunk.actions.end());
        rest.assign(chunk_rest.begin(), chunk_rest.end());
      } else {
        pending = std::move(chunk.actions);
        pending_rest = std::move(chunk_rest);
      }
    }
    // Thinking: the previous command stays, or (execute_while_thinking) the previous chunk's
    // rest runs on; otherwise execute the next action.
    if (thinking > 0) {
      std::optional<policy::Action> carried;
      if (!rest.empty()) {
        carried = std::move(rest.front());
        rest.pop_front();
      }
      if (--thinking == 0) {
        queue.assign(pending.begin(), pending.end());
        rest.assign(pending_rest.begin(), pending_rest.end());
      }
      episode.advance(carried ? &*carried : nullptr);
    } else {
      const policy::Action action = std::move(queue.front());
      queue.pop_front();
      episode.advance(&action);
    }
  }
  return episode.log();
}

EpisodeLog run_episode(const model::Model& model, sim::Data& data, policy::Policy& policy,
                       ScenarioDriver& driver, const EpisodeSetup& setup,
                       const RunOptions& options) {
  Episode episode(model, data, driver, policy.spec(), setup, options);
  return run_episode(episode, policy);
}

}  // namespace hribench::eval
