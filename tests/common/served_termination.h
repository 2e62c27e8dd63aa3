#pragma once
// The episode ending by which a simulated A1 stops where skilld's safety supervisor would stop it
// (tilt, height, joint range and speed; torque saturation and power are left out). The served
// training configs set these values; tests keep them equal to the supervisor's, and check
// libraries by them.

#include "server/server_config.h"
#include "sim/env_config.h"

namespace flsd::testutil {

inline TerminationConfig TerminationOf(const SafetyConfig& config) {
  TerminationConfig t;
  t.max_tilt = config.max_tilt;
  t.min_base_height = config.min_base_height;
  t.max_joint_speed = config.max_joint_velocity;
  t.max_joint_speed_time = config.max_joint_velocity_time;
  t.joint_range_margin = config.joint_range_margin;
  return t;
}

}  // namespace flsd::testutil
