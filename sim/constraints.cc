#include "sim/constraints.h"

#include <algorithm>
#include <cmath>

#include "robot/robot_state.h"
#include "sim/env.h"

namespace flsd {

double BaseHeightShortfall(const RobotState& state, const ConstraintLimits& limits) {
  return limits.min_moving_height - state.base_position.z();
}

std::array<float, kNumConstraints> MeasureViolations(const Env& env, const ConstraintLimits& limits) {
  const RobotState& s = env.state();
  std::array<float, kNumConstraints> out{};
  auto set = [&](Constraint c, double excess) { out[static_cast<int>(c)] = static_cast<float>(std::max(0.0, excess)); };

  set(Constraint::kFootSlip, env.FastestStanceFoot(limits.stance_force) - limits.slip_speed);
  const Eigen::Vector3d v = s.base_linear_velocity;
  const bool moving = std::hypot(v.x(), v.y()) > limits.moving_speed ||
                      std::abs(s.base_angular_velocity.z()) > limits.moving_yaw_rate;
  if (moving) set(Constraint::kLowBaseMoving, BaseHeightShortfall(s, limits));
  double speed = 0.0, range = 0.0;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    const double q = s.joint_position[j];
    speed = std::max(speed, std::abs(s.joint_velocity[j]));
    range = std::max({range, a1::JointMin(j) - q, q - a1::JointMax(j)});
  }
  set(Constraint::kJointSpeed, speed - limits.joint_speed);
  set(Constraint::kJointRange, range - limits.joint_range_margin);
  set(Constraint::kCalfContact, env.calf_contact() ? 1.0 : 0.0);
  return out;
}

}  // namespace flsd
