#include "server/safety.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace flsd {

namespace {

// A non-finite joint speed trips at once; a finite one is timed (SafetySupervisor::Check).
uint32_t NonFiniteSpeeds(const RobotState& state) {
  for (int j = 0; j < a1::kNumJoints; ++j) {
    if (!std::isfinite(state.joint_velocity[j])) return kFaultJointVelocity;
  }
  return 0;
}

}  // namespace

uint32_t SafetySupervisor::Hazards(const RobotState& state, const SafetyConfig& config) {
  // A low base is no hazard here: the robot may lie on the floor.
  return (BrokenLimits(state, config.limits) | NonFiniteSpeeds(state)) & ~kFaultLowBase;
}

uint32_t SafetySupervisor::Check(const RobotState& state, double dt, bool check_height) {
  uint32_t faults = BrokenLimits(state, config_.limits) | NonFiniteSpeeds(state);
  if (!check_height) faults &= ~kFaultLowBase;
  const StateLimits& limits = config_.limits;
  if (Outlasts(over_speed_.Update(FasterThan(state.joint_velocity, limits.max_joint_speed), dt),
               limits.max_joint_speed_time)) {
    faults |= kFaultJointVelocity;
  }
  const auto saturated = [&](int j) { return std::abs(state.joint_torque[j]) >= a1::kTorqueLimit - 1e-6; };
  if (Outlasts(saturated_.Update(saturated, dt), config_.max_torque_saturation)) faults |= kFaultTorque;
  over_power_time_ = !(Power(state) <= config_.max_power) ? over_power_time_ + dt : 0.0;
  if (Outlasts(over_power_time_, config_.max_power_time)) faults |= kFaultPower;
  return faults;
}

double SafetySupervisor::Power(const RobotState& state) {
  double power = 0.0;
  for (int j = 0; j < a1::kNumJoints; ++j) power += std::abs(state.joint_torque[j] * state.joint_velocity[j]);
  return power;
}

void SafetySupervisor::ClampTargets(a1::JointArray<double>& targets) {
  for (int j = 0; j < a1::kNumJoints; ++j) targets[j] = std::clamp(targets[j], a1::JointMin(j), a1::JointMax(j));
}

void DescribeFaults(uint32_t faults, const RobotState& state, const SafetyConfig& config, char* out,
                    std::size_t size, const char* backend) {
  if (size == 0) return;
  out[0] = '\0';
  std::size_t used = 0;
  auto add = [&](const char* fmt, auto... args) {
    if (used >= size) return;
    const int n = std::snprintf(out + used, size - used, fmt, used == 0 ? "" : "; ", args...);
    if (n > 0) used = std::min(size - 1, used + static_cast<std::size_t>(n));
  };
  // The worst offending joint, for the joint-wise faults.
  auto worst = [&](auto excess) {
    int arg = 0;
    for (int j = 1; j < a1::kNumJoints; ++j) {
      if (excess(j) > excess(arg)) arg = j;
    }
    return arg;
  };
  if (faults & kFaultStop) add("%semergency stop");
  if (faults & kFaultTilt) add("%stilt %.2f rad > %.2f", TiltOf(state), config.limits.max_tilt);
  if (faults & kFaultLowBase) add("%sbase height %.3f m < %.3f", state.base_position.z(), config.limits.min_base_height);
  if (faults & kFaultJointRange) {
    const int j = worst([&](int k) {
      const double q = state.joint_position[k];
      return std::isfinite(q) ? std::max(a1::JointMin(k) - q, q - a1::JointMax(k)) : HUGE_VAL;
    });
    add("%s%s at %.3f rad, outside [%.3f, %.3f]", a1::kJointNames[j], state.joint_position[j], a1::JointMin(j),
        a1::JointMax(j));
  }
  if (faults & kFaultJointVelocity) {
    const int j = worst([&](int k) {
      return std::isfinite(state.joint_velocity[k]) ? std::abs(state.joint_velocity[k]) : HUGE_VAL;
    });
    add("%s%s at %.1f rad/s > %.1f", a1::kJointNames[j], state.joint_velocity[j], config.limits.max_joint_speed);
  }
  if (faults & kFaultTorque) add("%storque at the %.1f N m limit for over %.2f s", a1::kTorqueLimit,
                                 config.max_torque_saturation);
  if (faults & kFaultPower) {
    add("%smotor power %.0f W above %.0f W for over %.2f s", SafetySupervisor::Power(state), config.max_power,
        config.max_power_time);
  }
  if (faults & kFaultBackend) {
    if (backend != nullptr && backend[0] != '\0') add("%sbackend: %s", backend);
    else add("%sbackend state not trusted");
  }
  if (faults & kFaultPolicy) add("%spolicy produced a non-finite action");
}

}  // namespace flsd
