#pragma once
// The 500 Hz driver's fault logic, apart from its socket and its clock: fed each valid state frame
// with the time it arrived, and asked at any time, it says whether the driver must damp and why.
// Time is a parameter, so tests step it frame by frame without sleeping.

#include <chrono>

#include "hw/a1_protocol.h"
#include "hw/hw_config.h"
#include "robot/backend.h"

namespace flsd::hw {

enum class DriverFault : int { kNone, kStale, kFrozenImu, kFrozenJoints, kMotorMode, kNoCommand };

class DriverMonitor {
 public:
  using Time = std::chrono::steady_clock::time_point;

  // Counts staleness from `start`: no frame by stale_after after it is a fault.
  DriverMonitor(const HwConfig& config, Time start);

  // A valid (CRC-checked, plausible) frame that arrived at `now`, while the driver sent `command`:
  // its gains say which motors must be in servo mode.
  void OnFrame(const LowState& frame, const JointCommand& command, Time now);

  // The fault at `now`. `command_lost`: the control loop has stopped handing commands over (the
  // driver's watchdog), which outranks what the frames say.
  DriverFault Check(bool command_lost, Time now) const;

  // Seconds since the last valid frame (or since start).
  double SinceValid(Time now) const;
  // The joint that was last out of servo mode while commanded; -1 if none has been.
  int motor_mode_joint() const { return motor_mode_joint_; }

 private:
  // How long one sensor's readings have repeated, judged on its own: a hung IMU is caught while
  // the encoders still move (a fall would otherwise go unseen).
  struct FreezeTimer {
    bool frozen = false;
    Time since;
    void Update(bool same, Time now);
    // Judged up to the last valid frame: without frames it is a stale state, not a freeze.
    bool Outlasts(double seconds, Time last_frame) const;
  };

  HwConfig config_;
  Time last_valid_;
  bool have_frame_ = false;
  LowState previous_;
  FreezeTimer imu_frozen_, joints_frozen_;
  bool mode_bad_ = false;
  Time mode_bad_since_;
  int motor_mode_joint_ = -1;
};

}  // namespace flsd::hw
