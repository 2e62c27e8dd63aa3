#pragma once
// The safety supervisor: checks every measured state while the motors hold the robot, and says
// which limits are broken. The controller latches any trip into damping; it never exits.

#include <cstdint>
#include <cstddef>

#include "robot/joint_limit_timer.h"
#include "robot/robot_state.h"
#include "robot/state_limits.h"
#include "server/server_config.h"

namespace flsd {

// Fault bits, as published in telemetry (RobotState.faults).
enum FaultBit : uint32_t {
  kFaultTilt = kBreaksTilt,              // attitude beyond max_tilt: a fall
  kFaultLowBase = kBreaksBaseHeight,     // base below min_base_height: a fall
  kFaultJointRange = kBreaksJointRange,  // a joint outside its range by more than the margin
  kFaultJointVelocity = 1u << 3,  // a joint faster than max_joint_velocity for too long
  kFaultTorque = 1u << 4,         // a joint at the torque limit for longer than allowed
  kFaultBackend = 1u << 5,        // the backend's state cannot be trusted
  kFaultPolicy = 1u << 6,         // the policy produced a non-finite action
  kFaultStop = 1u << 7,           // an emergency stop (damp) from a client
  kFaultPower = 1u << 8,          // mechanical power sum |tau qdot| above its limit for too long
};

// Writes "tilt 1.31 rad > 1.00; ..." for `faults` into out (always terminated); `backend` is the
// backend's own account of a kFaultBackend.
void DescribeFaults(uint32_t faults, const RobotState& state, const SafetyConfig& config, char* out,
                    std::size_t size, const char* backend = nullptr);

class SafetySupervisor {
 public:
  explicit SafetySupervisor(const SafetyConfig& config) : config_(config) {}

  // The limits `state` breaks, one control period `dt` after the previous check. Torque
  // saturation is timed across calls; Reset() forgets it (call it when the motors go slack).
  // `check_height`: false while the robot rises from the floor, where a low base is expected.
  uint32_t Check(const RobotState& state, double dt, bool check_height = true);
  void Reset() {
    saturated_.Reset();
    over_speed_.Reset();
    over_power_time_ = 0.0;
  }
  // Mechanical power of the 12 motors, sum of |tau qdot|, W (the vendor SDK's PowerProtect sum).
  static double Power(const RobotState& state);

  // Clamps joint targets into the A1's joint ranges.
  static void ClampTargets(a1::JointArray<double>& targets);

  // What makes it unsafe to put stiffness on the joints at all, whatever the mode: a robot on
  // its side, a joint out of range, a non-finite reading. Stateless.
  static uint32_t Hazards(const RobotState& state, const SafetyConfig& config);

  const SafetyConfig& config() const { return config_; }

 private:
  SafetyConfig config_;
  JointLimitTimer saturated_;   // at the torque limit
  JointLimitTimer over_speed_;  // past max_joint_velocity
  double over_power_time_ = 0.0;
};

}  // namespace flsd
