#include "eval/constants.h"

namespace hribench::eval {

std::vector<NamedConstant> constant_table(const MetricConstants& c) {
  return {
      {"moving_ee_speed", c.moving_ee_speed, "m/s"},
      {"moving_gripper_rate", c.moving_gripper_rate, "m/s"},
      {"moving_sustain", c.moving_sustain, "s"},
      {"still_ee_speed", c.still_ee_speed, "m/s"},
      {"still_gripper_rate", c.still_gripper_rate, "m/s"},
      {"still_sustain", c.still_sustain, "s"},
      {"response_speed", c.response_speed, "m/s"},
      {"response_sustain", c.response_sustain, "s"},
      {"goal_reached_distance", c.goal_reached_distance, "m"},
      {"success_hold", c.success_hold, "s"},
      {"environment_collision_force", c.environment_collision_force, "N"},
      {"any_collision_force", c.any_collision_force, "N"},
      {"monitored_distance", c.monitored_distance, "m"},
      {"human_speed", c.human_speed, "m/s"},
      {"human_speed_near", c.human_speed_near, "m/s"},
      {"human_speed_near_distance", c.human_speed_near_distance, "m"},
      {"reaction_time", c.reaction_time, "s"},
      {"stop_deceleration", c.stop_deceleration, "m/s^2"},
      {"intrusion_distance", c.intrusion_distance, "m"},
      {"position_uncertainty", c.position_uncertainty, "m"},
      {"permitted_speed", c.permitted_speed, "m/s"},
      {"permitted_distance", c.permitted_distance, "m"},
      {"transient_factor", c.transient_factor, ""},
      {"desync_below", c.desync_below, ""},
      {"unsafe_proximity_below", c.unsafe_proximity_below, ""},
      {"time_epsilon", c.time_epsilon, "s"},
      {"confidence", c.confidence, ""},
      {"wilson_z", c.wilson_z, ""},
      {"bootstrap_resamples", static_cast<double>(c.bootstrap_resamples), "count"},
      {"bootstrap_seed", static_cast<double>(c.bootstrap_seed), ""},
  };
}

}  // namespace hribench::eval
