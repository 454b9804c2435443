#include "eval/robot_motion.h"

#include <cmath>
#include <functional>

namespace hribench::eval {
namespace {

// Runs of consecutive step intervals k (between steps k-1 and k) where `holds(k)` is true,
// kept if at least `sustain` long.
TimeSet sustained_runs(const EpisodeLog& log, const std::function<bool(size_t)>& holds,
                       double sustain, double epsilon) {
  TimeSet runs;
  const auto& s = log.steps;
  size_t k = 1;
  while (k < s.size()) {
    if (!holds(k)) {
      ++k;
      continue;
    }
    const size_t first = k;
    while (k < s.size() && holds(k)) ++k;
    const TimeInterval run{s[first - 1].time, s[k - 1].time};
    if (run.length() >= sustain - epsilon) runs.push_back(run);
  }
  return runs;
}

double dt(const EpisodeLog& log, size_t k) { return log.steps[k].time - log.steps[k - 1].time; }

core::Vec3 ee_velocity(const EpisodeLog& log, size_t k) {
  return (log.steps[k].X_WT.translation - log.steps[k - 1].X_WT.translation) / dt(log, k);
}

double gripper_rate(const EpisodeLog& log, size_t k) {
  return std::abs(log.steps[k].gripper_width - log.steps[k - 1].gripper_width) / dt(log, k);
}

// The gripper's rate over interval k where its width changes toward the opening the robot
// commanded over that interval, else 0: fingers settling back on a grasped object (or pushed
// open by it) move away from the command, and the robot is not moving its gripper.
double commanded_gripper_rate(const EpisodeLog& log, size_t k) {
  const StepRecord& from = log.steps[k - 1];
  const StepRecord& to = log.steps[k];
  const bool toward = (to.gripper_target - from.gripper_width) * (to.gripper_width - from.gripper_width) > 0;
  return toward ? gripper_rate(log, k) : 0.0;
}

}  // namespace

TimeSet moving_time(const EpisodeLog& log, const MetricConstants& c) {
  return sustained_runs(
      log,
      [&](size_t k) {
        return ee_velocity(log, k).norm() > c.moving_ee_speed ||
               commanded_gripper_rate(log, k) > c.moving_gripper_rate;
      },
      c.moving_sustain, c.time_epsilon);
}

TimeSet still_time(const EpisodeLog& log, const MetricConstants& c) {
  return sustained_runs(
      log,
      [&](size_t k) {
        return ee_velocity(log, k).norm() < c.still_ee_speed &&
               gripper_rate(log, k) < c.still_gripper_rate;
      },
      c.still_sustain, c.time_epsilon);
}

TimeSet toward_time(const EpisodeLog& log, const core::Vec3& goal_W, const MetricConstants& c) {
  return sustained_runs(
      log,
      [&](size_t k) {
        // Direction to the goal from where the interval started.
        const core::Vec3 to_goal = goal_W - log.steps[k - 1].X_WT.translation;
        const double distance = to_goal.norm();
        if (distance < c.goal_reached_distance) return false;
        return ee_velocity(log, k).dot(to_goal / distance) > c.response_speed;
      },
      c.response_sustain, c.time_epsilon);
}

TimeSet retreat_time(const EpisodeLog& log, const MetricConstants& c) {
  return sustained_runs(
      log, [&](size_t k) { return log.steps[k].approach_speed < -c.response_speed; },
      c.response_sustain, c.time_epsilon);
}

std::optional<double> first_time_at_or_after(const TimeSet& set, double t, double epsilon) {
  for (const TimeInterval& i : set) {
    if (i.to <= t + epsilon) continue;  // ended at or before t
    return i.from > t ? i.from : t;
  }
  return std::nullopt;
}

std::optional<TimeInterval> interval_across(const TimeSet& set, double t, double epsilon) {
  for (const TimeInterval& i : set) {
    if (i.from <= t + epsilon && i.to > t + epsilon) return i;
  }
  return std::nullopt;
}

}  // namespace hribench::eval
