#include "robot/state_limits.h"

#include <algorithm>
#include <cmath>

#include "robot/robot_state.h"

namespace flsd {

double TiltOf(const RobotState& state) {
  const double cos_tilt = -state.ProjectedGravity().z();
  return std::acos(std::clamp(cos_tilt, -1.0, 1.0));
}

// Every limit is written so that a NaN breaks it: !(x <= limit) is true for NaN, x > limit is not.
uint32_t BrokenLimits(const RobotState& state, const StateLimits& limits) {
  uint32_t broken = 0;
  if (!(TiltOf(state) <= limits.max_tilt)) broken |= kBreaksTilt;
  if (limits.min_base_height > 0.0 && !(state.base_position.z() >= limits.min_base_height)) broken |= kBreaksBaseHeight;
  if (limits.joint_range_margin >= 0.0) {
    for (int j = 0; j < a1::kNumJoints; ++j) {
      if (!a1::WithinRange(j, state.joint_position[j], limits.joint_range_margin)) broken |= kBreaksJointRange;
    }
  }
  return broken;
}

}  // namespace flsd
