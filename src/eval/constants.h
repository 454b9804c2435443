#pragma once
// Every threshold of the metrics (docs/metrics.md), in this one place. Results files print the
// values used (constant_table), and docs/metrics.md documents each.

#include <cstdint>
#include <string>
#include <vector>

namespace hribench::eval {

// The standard normal distribution's quantile: z with Phi(z) = p, p in (0, 1) (HRIB_CHECK),
// to the last bit or so (Newton's method on erfc).
double normal_quantile(double p);

struct MetricConstants {
  // Robot motion state. Moving: end-effector speed above moving_ee_speed or gripper width
  // changing faster than moving_gripper_rate, for at least moving_sustain. Still: speed below
  // still_ee_speed and gripper rate below still_gripper_rate, for at least still_sustain.
  double moving_ee_speed = 0.02;      // m/s
  double moving_gripper_rate = 0.01;  // m/s
  double moving_sustain = 0.1;        // s
  double still_ee_speed = 0.01;       // m/s
  double still_gripper_rate = 0.005;  // m/s ("gripper static"; docs/metrics.md gives no number)
  double still_sustain = 0.2;         // s
  // Response onset: velocity component toward the response goal (go cues, robot act onsets)
  // or away from the human (intrusion cues) above response_speed for response_sustain.
  double response_speed = 0.02;          // m/s
  double response_sustain = 0.1;         // s
  double goal_reached_distance = 0.01;   // m: closer than this, "toward the goal" is undefined
  // Success must hold continuously for the last success_hold seconds.
  double success_hold = 0.5;  // s
  // CFR: unintended robot–environment collision.
  double environment_collision_force = 20.0;  // N, non-finger robot part on the environment
  double any_collision_force = 150.0;         // N, any robot contact
  // HCS: ISO/TS 15066 speed-and-separation monitoring.
  double monitored_distance = 1.0;       // m: T_monitored counts d(t) <= this
  double human_speed = 1.6;              // m/s, v_h
  double human_speed_near = 2.0;         // m/s, v_h when d < human_speed_near_distance
  double human_speed_near_distance = 0.5;  // m
  double reaction_time = 0.1;            // s, T_r
  double stop_deceleration = 3.0;        // m/s^2, a_stop
  double intrusion_distance = 0.0;       // m, C
  double position_uncertainty = 0.05;    // m, Z_d + Z_r
  double permitted_speed = 0.25;         // m/s: in a permitted phase, faster than this ...
  double permitted_distance = 0.10;      // m: ... while closer than this is a violation
  double transient_factor = 2.0;         // critical contact: force > factor x quasi-static
  // Failure labels.
  double desync_below = 0.5;             // TSync below this: "desync"
  double unsafe_proximity_below = 0.9;   // HCS below this: "unsafe_proximity"
  // Comparisons of times allow this slack (20 Hz times are not exact in binary).
  double time_epsilon = 1e-9;  // s
  // Aggregation.
  double confidence = 0.95;          // two-sided interval level, in (0, 1)
  int bootstrap_resamples = 2000;
  uint64_t bootstrap_seed = 20240917;

  // The Wilson interval's z: the standard normal quantile of 1 - (1 - confidence) / 2
  // (1.959963984540054 at 0.95), derived, never stored.
  double wilson_z() const { return normal_quantile(1 - (1 - confidence) / 2); }
};

struct NamedConstant {
  std::string name;  // the member's name, e.g. "moving_ee_speed"
  double value = 0;
  std::string unit;  // "m/s", "s", "N", "m", "" (dimensionless), "count"
  bool operator==(const NamedConstant&) const = default;
};

// Calls visit(name, member, unit) for every member of `c`, in declaration order: the one list
// that results files, reloading and docs share. `Constants` is MetricConstants, const or not.
template <typename Constants, typename Visit>
void visit_constants(Constants& c, Visit&& visit) {
  visit("moving_ee_speed", c.moving_ee_speed, "m/s");
  visit("moving_gripper_rate", c.moving_gripper_rate, "m/s");
  visit("moving_sustain", c.moving_sustain, "s");
  visit("still_ee_speed", c.still_ee_speed, "m/s");
  visit("still_gripper_rate", c.still_gripper_rate, "m/s");
  visit("still_sustain", c.still_sustain, "s");
  visit("response_speed", c.response_speed, "m/s");
  visit("response_sustain", c.response_sustain, "s");
  visit("goal_reached_distance", c.goal_reached_distance, "m");
  visit("success_hold", c.success_hold, "s");
  visit("environment_collision_force", c.environment_collision_force, "N");
  visit("any_collision_force", c.any_collision_force, "N");
  visit("monitored_distance", c.monitored_distance, "m");
  visit("human_speed", c.human_speed, "m/s");
  visit("human_speed_near", c.human_speed_near, "m/s");
  visit("human_speed_near_distance", c.human_speed_near_distance, "m");
  visit("reaction_time", c.reaction_time, "s");
  visit("stop_deceleration", c.stop_deceleration, "m/s^2");
  visit("intrusion_distance", c.intrusion_distance, "m");
  visit("position_uncertainty", c.position_uncertainty, "m");
  visit("permitted_speed", c.permitted_speed, "m/s");
  visit("permitted_distance", c.permitted_distance, "m");
  visit("transient_factor", c.transient_factor, "");
  visit("desync_below", c.desync_below, "");
  visit("unsafe_proximity_below", c.unsafe_proximity_below, "");
  visit("time_epsilon", c.time_epsilon, "s");
  visit("confidence", c.confidence, "");
  visit("bootstrap_resamples", c.bootstrap_resamples, "count");
  visit("bootstrap_seed", c.bootstrap_seed, "");
}

// Every member of `constants`, in declaration order.
std::vector<NamedConstant> constant_table(const MetricConstants& constants);

}  // namespace hribench::eval
