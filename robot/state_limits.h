#pragma once
// The limits a robot's state must keep, one struct for both ends: skilld's safety supervisor stops
// the robot past them (server/safety.h), and training ends an episode past them (sim/env.h), so
// that skills can learn within the limits they will be served under. Each end reads them under its
// own config keys and defaults (server/server_config.h, sim/env_config.h).

#include <cstdint>

#include "robot/a1.h"

namespace flsd {

struct RobotState;  // robot/robot_state.h; the configs that hold StateLimits need no Eigen

struct StateLimits {
  double max_tilt = 1.0;            // rad from upright
  double min_base_height = 0.12;    // m; 0 turns the check off
  double joint_range_margin = 0.1;  // rad a joint may be outside the A1's range; negative turns it off
  // rad/s; 0 turns it off. A joint past it for longer than max_joint_speed_time breaks the limit,
  // timed by the caller (robot/joint_limit_timer.h).
  double max_joint_speed = a1::kJointVelocityLimit;
  double max_joint_speed_time = a1::kJointOverspeedTolerance;
};

// The tilt of the base from upright, rad; NaN for a non-finite attitude.
double TiltOf(const RobotState& state);

// The limits of one state alone (the joint speed, which is timed, aside). The bits are skilld's
// fault bits for the same limits (server/safety.h).
enum StateLimitBit : uint32_t {
  kBreaksTilt = 1u << 0,
  kBreaksBaseHeight = 1u << 1,
  kBreaksJointRange = 1u << 2,
};
// The limits `state` breaks. A NaN breaks every limit it enters.
uint32_t BrokenLimits(const RobotState& state, const StateLimits& limits);

}  // namespace flsd
