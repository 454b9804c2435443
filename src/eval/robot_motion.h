#pragma once
// Robot motion state from an EpisodeLog (docs/metrics.md notation): when the robot is *moving* and
// when it is *still*, and response onsets. Pure functions of the log.
//
// The log samples the world at control steps t_0 < t_1 < ...; a motion quantity belongs to the
// interval [t_{k-1}, t_k] between two steps: end-effector speed |p_k - p_{k-1}| / (t_k -
// t_{k-1}), gripper rate |w_k - w_{k-1}| / (t_k - t_{k-1}) (for *moving*, only where the width
// changes toward the opening commanded over the interval, StepRecord::gripper_target).
// Quantities the log samples directly (separation, approach speed) are assigned to the
// interval that ends at their step.
// A condition "sustained D" holds on the union of the maximal runs of consecutive intervals
// where it holds whose total length is at least D.

#include <optional>

#include "core/math.h"
#include "eval/constants.h"
#include "eval/episode_log.h"
#include "eval/timeline.h"

namespace hribench::eval {

// The intervals of the log in which the robot is moving / still (sustained runs).
TimeSet moving_time(const EpisodeLog& log, const MetricConstants& c);
TimeSet still_time(const EpisodeLog& log, const MetricConstants& c);
// Sustained runs of end-effector velocity component toward goal_W above c.response_speed.
TimeSet toward_time(const EpisodeLog& log, const core::Vec3& goal_W, const MetricConstants& c);
// Sustained runs of the robot's closest point moving away from the human (approach speed
// below -c.response_speed).
TimeSet retreat_time(const EpisodeLog& log, const MetricConstants& c);

// The first time >= t in `set`: t itself if t lies inside an interval that goes on after t,
// else the start of the next interval; nullopt if none. (The onset of a sustained state at or
// after t.)
std::optional<double> first_time_at_or_after(const TimeSet& set, double t, double epsilon);
// The interval of `set` under way at t: it began at or before t and goes on after t; nullopt
// if none. (The sustained state a cue finds the robot in, and when it began.)
std::optional<TimeInterval> interval_across(const TimeSet& set, double t, double epsilon);

}  // namespace hribench::eval
