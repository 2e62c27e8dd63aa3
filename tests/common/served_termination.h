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
  t.limits = config.limits;
  return t;
}

}  // namespace flsd::testutil
