#include "hw/driver_monitor.h"

#include <cmath>

namespace flsd::hw {
namespace {

double Seconds(std::chrono::steady_clock::duration d) { return std::chrono::duration<double>(d).count(); }

// Bit-identical IMU readings: a real IMU's noise never repeats frame after frame.
bool SameImu(const LowState& a, const LowState& b) {
  return a.imu.quaternion == b.imu.quaternion && a.imu.gyroscope == b.imu.gyroscope &&
         a.imu.accelerometer == b.imu.accelerometer;
}

// Bit-identical joint encoder readings.
bool SameJoints(const LowState& a, const LowState& b) {
  for (int j = 0; j < a1::kNumJoints; ++j) {
    if (a.motors[j].q != b.motors[j].q || a.motors[j].dq != b.motors[j].dq) return false;
  }
  return true;
}

// Whether the IMU says the body turns: far above its noise (about 0.01 rad/s).
bool Turning(const LowState& frame) {
  const auto& g = frame.imu.gyroscope;
  return std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) > 0.1f;
}

}  // namespace

void DriverMonitor::FreezeTimer::Update(bool same, Time now) {
  if (same && !frozen) since = now;
  frozen = same;
}

bool DriverMonitor::FreezeTimer::Outlasts(double seconds, Time last_frame) const {
  return frozen && Seconds(last_frame - since) > seconds;
}

DriverMonitor::DriverMonitor(const HwConfig& config, Time start)
    : config_(config), last_valid_(start), mode_bad_since_(start) {}

void DriverMonitor::OnFrame(const LowState& frame, const JointCommand& command, Time now) {
  last_valid_ = now;
  imu_frozen_.Update(have_frame_ && SameImu(frame, previous_), now);
  // The encoders of a robot at rest may repeat (they are quantised, and dq is then 0): they are
  // frozen only if they repeat while the IMU says the body turns.
  joints_frozen_.Update(have_frame_ && SameJoints(frame, previous_) && Turning(frame), now);
  bool any_mode_bad = false;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    if ((command.kp[j] != 0.0 || command.kd[j] != 0.0) && frame.motors[j].mode != kModeServo) {
      any_mode_bad = true;
      motor_mode_joint_ = j;
    }
  }
  if (any_mode_bad && !mode_bad_) mode_bad_since_ = now;
  mode_bad_ = any_mode_bad;
  previous_ = frame;
  have_frame_ = true;
}

DriverFault DriverMonitor::Check(bool command_lost, Time now) const {
  if (command_lost) return DriverFault::kNoCommand;
  if (SinceValid(now) > config_.stale_after) return DriverFault::kStale;
  if (imu_frozen_.Outlasts(config_.frozen_after, last_valid_)) return DriverFault::kFrozenImu;
  if (joints_frozen_.Outlasts(config_.frozen_after, last_valid_)) return DriverFault::kFrozenJoints;
  if (mode_bad_ && Seconds(now - mode_bad_since_) > config_.motor_mode_after) return DriverFault::kMotorMode;
  return DriverFault::kNone;
}

double DriverMonitor::SinceValid(Time now) const { return Seconds(now - last_valid_); }

}  // namespace flsd::hw
