// The driver's fault logic on a clock the test steps: each fault appears exactly when its
// threshold is passed, not a frame before, and the faults that must not be (encoders at rest,
// an unpowered motor that nothing commands) never are.

#include "hw/driver_monitor.h"

#include <gtest/gtest.h>

#include <chrono>
#include <optional>

namespace flsd::hw {
namespace {

using namespace std::chrono_literals;
using Time = DriverMonitor::Time;

constexpr auto kPeriod = 2ms;  // the driver's 500 Hz

// A healthy robot's frame number `i`: noisy IMU and moving encoders, every motor in servo mode.
LowState Frame(int i) {
  LowState f;
  f.imu.gyroscope = {0.001f * static_cast<float>(i % 7), 0.0f, 0.0f};
  f.imu.accelerometer = {0.0f, 0.0f, 9.81f + 0.001f * static_cast<float>(i % 5)};
  for (int j = 0; j < a1::kNumJoints; ++j) {
    f.motors[j].mode = kModeServo;
    f.motors[j].q = 0.001f * static_cast<float>(i % 11);
  }
  return f;
}

class DriverMonitorTest : public ::testing::Test {
 protected:
  // Feeds `frames` frames 2 ms apart, each made by `make(i)` under `command`; returns the first
  // time the monitor reports a fault (checked after every frame, as the driver does), or nothing.
  template <class Make>
  std::optional<std::chrono::milliseconds> FirstFault(int frames, Make make, const JointCommand& command = {}) {
    for (int i = 0; i < frames; ++i) {
      now_ += kPeriod;
      monitor_.OnFrame(make(i), command, now_);
      if (monitor_.Check(false, now_) != DriverFault::kNone) {
        return std::chrono::duration_cast<std::chrono::milliseconds>(now_ - start_);
      }
    }
    return std::nullopt;
  }
  void Restart() { start_ = now_; }

  HwConfig config_;  // stale_after, frozen_after 0.1 s; motor_mode_after 0.05 s
  Time start_{std::chrono::seconds(1000)};
  Time now_ = start_;
  DriverMonitor monitor_{config_, start_};
};

TEST_F(DriverMonitorTest, AHealthyRobotHasNoFault) {
  EXPECT_FALSE(FirstFault(2000, Frame).has_value());
  EXPECT_EQ(monitor_.Check(false, now_), DriverFault::kNone);
  EXPECT_DOUBLE_EQ(monitor_.SinceValid(now_), 0.0);
}

TEST_F(DriverMonitorTest, NoFrameIsStaleOnlyAfterStaleAfter) {
  EXPECT_EQ(monitor_.Check(false, start_ + 100ms), DriverFault::kNone);  // not more than 0.1 s yet
  EXPECT_EQ(monitor_.Check(false, start_ + 101ms), DriverFault::kStale);
  FirstFault(10, Frame);
  const Time last = now_;
  EXPECT_EQ(monitor_.Check(false, last + 100ms), DriverFault::kNone);
  EXPECT_EQ(monitor_.Check(false, last + 101ms), DriverFault::kStale);
  EXPECT_NEAR(monitor_.SinceValid(last + 101ms), 0.101, 1e-9);
}

TEST_F(DriverMonitorTest, AFrozenImuIsAFaultAfterFrozenAfterWhileTheEncodersMove) {
  FirstFault(10, Frame);
  Restart();
  const LowState held = Frame(3);
  const auto fault = FirstFault(200, [&](int i) {
    LowState f = Frame(i);
    f.imu = held.imu;
    return f;
  });
  ASSERT_TRUE(fault.has_value());
  EXPECT_EQ(monitor_.Check(false, now_), DriverFault::kFrozenImu);
  // The first repeat (the second frame) starts the timer; the fault is the first frame more than
  // 0.1 s after it.
  EXPECT_EQ(*fault, 2 * kPeriod + 102ms);
}

TEST_F(DriverMonitorTest, EncodersThatRepeatAreFrozenOnlyWhileTheBodyTurns) {
  const auto at_rest = [](int i) {
    LowState f = Frame(i);
    for (int j = 0; j < a1::kNumJoints; ++j) f.motors[j].q = 0.5f;  // quantised, still
    return f;
  };
  EXPECT_FALSE(FirstFault(500, at_rest).has_value());
  Restart();
  const auto fault = FirstFault(200, [&](int i) {
    LowState f = at_rest(i);
    f.imu.gyroscope = {0.5f + 0.001f * static_cast<float>(i), 0.0f, 0.0f};  // turning
    return f;
  });
  ASSERT_TRUE(fault.has_value());
  EXPECT_EQ(monitor_.Check(false, now_), DriverFault::kFrozenJoints);
  EXPECT_EQ(*fault, kPeriod + 102ms);  // the first turning frame starts the timer
}

TEST_F(DriverMonitorTest, AFreezeIsJudgedOnlyUpToTheLastFrame) {
  // A sensor that repeats and then goes silent is a stale robot, not a frozen sensor: the freeze
  // timer stops with the frames.
  const LowState held = Frame(1);
  FirstFault(20, [&](int) { return held; });
  EXPECT_EQ(monitor_.Check(false, now_ + 60ms), DriverFault::kNone);
  EXPECT_EQ(monitor_.Check(false, now_ + 101ms), DriverFault::kStale);
}

TEST_F(DriverMonitorTest, AMotorOutOfServoModeIsAFaultOnlyOnceCommanded) {
  const auto dead_motor = [](int i) {
    LowState f = Frame(i);
    f.motors[4].mode = 0;
    return f;
  };
  EXPECT_FALSE(FirstFault(500, dead_motor).has_value());  // zero gains: nothing asked of it
  Restart();
  const auto fault = FirstFault(200, dead_motor, JointCommand::Damp(1.0));
  ASSERT_TRUE(fault.has_value());
  EXPECT_EQ(monitor_.Check(false, now_), DriverFault::kMotorMode);
  EXPECT_EQ(monitor_.motor_mode_joint(), 4);
  EXPECT_EQ(*fault, kPeriod + 52ms);  // more than motor_mode_after (0.05 s) after the first
}

TEST_F(DriverMonitorTest, ALostCommandOutranksEverythingAndClearsWithIt) {
  FirstFault(10, Frame);
  EXPECT_EQ(monitor_.Check(true, now_ + 200ms), DriverFault::kNoCommand);  // even when also stale
  EXPECT_EQ(monitor_.Check(false, now_), DriverFault::kNone);
}

}  // namespace
}  // namespace flsd::hw
