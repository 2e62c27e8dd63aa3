// SafetySupervisor: each limit trips at its threshold and not below it, torque saturation is
// timed, targets are clamped into the joint ranges, and the fault text names the culprit.

#include "server/safety.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "sim/env.h"
#include "tests/common/robot_states.h"
#include "tests/common/served_termination.h"

namespace flsd {
namespace {

using testutil::TerminationOf;

using ::testing::HasSubstr;

using testutil::Standing;

RobotState Rolled(double angle) { return testutil::Turned(Eigen::Vector3d::UnitX(), angle); }

TEST(SafetySupervisor, StandingRobotBreaksNoLimit) {
  SafetySupervisor supervisor{SafetyConfig{}};
  EXPECT_EQ(supervisor.Check(Standing(), 0.02), 0u);
}

TEST(SafetySupervisor, TiltIsTheAngleFromUpright) {
  EXPECT_NEAR(TiltOf(Rolled(0.7)), 0.7, 1e-9);
  EXPECT_NEAR(TiltOf(Rolled(-2.5)), 2.5, 1e-9);
}

TEST(SafetySupervisor, TiltTripsJustPastTheLimit) {
  SafetyConfig config;
  config.limits.max_tilt = 1.0;
  SafetySupervisor supervisor(config);
  EXPECT_EQ(supervisor.Check(Rolled(0.99), 0.02), 0u);
  EXPECT_EQ(supervisor.Check(Rolled(1.01), 0.02), kFaultTilt);
}

TEST(SafetySupervisor, NonFiniteReadingsBreakEveryLimit) {
  SafetySupervisor supervisor{SafetyConfig{}};
  RobotState s = Standing();
  s.base_orientation.coeffs().setConstant(NAN);
  EXPECT_NE(supervisor.Check(s, 0.02) & kFaultTilt, 0u);
  s = Standing();
  s.base_position.z() = NAN;
  EXPECT_EQ(supervisor.Check(s, 0.02), kFaultLowBase);
  s = Standing();
  s.joint_velocity[3] = NAN;
  EXPECT_EQ(supervisor.Check(s, 0.02), kFaultJointVelocity);
  EXPECT_EQ(SafetySupervisor::Hazards(s, SafetyConfig{}), kFaultJointVelocity);
}

TEST(SafetySupervisor, LowBaseTripsUnlessHeightIsNotChecked) {
  SafetyConfig config;
  config.limits.min_base_height = 0.12;
  SafetySupervisor supervisor(config);
  RobotState s = Standing();
  s.base_position.z() = 0.11;
  EXPECT_EQ(supervisor.Check(s, 0.02), kFaultLowBase);
  EXPECT_EQ(supervisor.Check(s, 0.02, /*check_height=*/false), 0u);
  config.limits.min_base_height = 0.0;  // off
  EXPECT_EQ(SafetySupervisor(config).Check(s, 0.02), 0u);
}

TEST(SafetySupervisor, JointOutsideItsRangeByMoreThanTheMarginTrips) {
  SafetyConfig config;
  config.limits.joint_range_margin = 0.1;
  SafetySupervisor supervisor(config);
  RobotState s = Standing();
  s.joint_position[2] = a1::JointMin(2) - 0.09;  // FR calf, inside the margin
  EXPECT_EQ(supervisor.Check(s, 0.02), 0u);
  s.joint_position[2] = a1::JointMin(2) - 0.11;
  EXPECT_EQ(supervisor.Check(s, 0.02), kFaultJointRange);
  s.joint_position[2] = NAN;
  EXPECT_EQ(supervisor.Check(s, 0.02), kFaultJointRange);
}

TEST(SafetySupervisor, JointVelocityTripsWhenItStaysAboveTheLimitLongerThanAFootStrike) {
  SafetySupervisor supervisor{SafetyConfig{}};  // 21 rad/s for at most 0.04 s
  RobotState s = Standing();
  s.joint_velocity[7] = -20.9;
  EXPECT_EQ(supervisor.Check(s, 0.02), 0u);
  // One tick past it, as a foot strike gives, then back under: no trip, and the time restarts.
  s.joint_velocity[7] = -21.1;
  EXPECT_EQ(supervisor.Check(s, 0.02), 0u);
  s.joint_velocity[7] = -15.0;
  EXPECT_EQ(supervisor.Check(s, 0.02), 0u);
  // Three ticks past it (0.06 s) trip on the third.
  s.joint_velocity[7] = -21.1;
  EXPECT_EQ(supervisor.Check(s, 0.02), 0u);
  EXPECT_EQ(supervisor.Check(s, 0.02), 0u);
  EXPECT_EQ(supervisor.Check(s, 0.02), kFaultJointVelocity);
  // With no time allowed, the first sample past the limit trips.
  SafetyConfig strict;
  strict.limits.max_joint_speed_time = 0.0;
  EXPECT_EQ(SafetySupervisor(strict).Check(s, 0.02), kFaultJointVelocity);
}

TEST(SafetySupervisor, TorqueSaturationTripsAfterItsTimeAndResetsWhenItEnds) {
  SafetyConfig config;
  config.max_torque_saturation = 0.5;
  SafetySupervisor supervisor(config);
  RobotState s = Standing();
  s.joint_torque[4] = a1::kTorqueLimit;
  // 25 ticks of 20 ms reach exactly 0.5 s: not yet over it.
  for (int tick = 0; tick < 25; ++tick) ASSERT_EQ(supervisor.Check(s, 0.02), 0u) << "tick " << tick;
  EXPECT_EQ(supervisor.Check(s, 0.02), kFaultTorque);

  s.joint_torque[4] = 10.0;  // off the limit: the clock restarts
  EXPECT_EQ(supervisor.Check(s, 0.02), 0u);
  s.joint_torque[4] = -a1::kTorqueLimit;
  EXPECT_EQ(supervisor.Check(s, 0.02), 0u);
  supervisor.Reset();
  for (int tick = 0; tick < 25; ++tick) ASSERT_EQ(supervisor.Check(s, 0.02), 0u);
}

TEST(SafetySupervisor, PowerAboveTheLimitTripsAfterItsTime) {
  SafetyConfig config;
  config.max_power = 1000.0;
  config.max_power_time = 0.1;
  SafetySupervisor supervisor(config);
  RobotState s = Standing();
  s.joint_torque[1] = 30.0;
  s.joint_velocity[1] = -20.0;  // 600 W
  s.joint_torque[4] = -25.0;
  s.joint_velocity[4] = 18.0;   // 450 W: 1050 W in all
  EXPECT_DOUBLE_EQ(SafetySupervisor::Power(s), 1050.0);
  for (int tick = 0; tick < 5; ++tick) ASSERT_EQ(supervisor.Check(s, 0.02), 0u) << "tick " << tick;
  EXPECT_EQ(supervisor.Check(s, 0.02), kFaultPower);
  s.joint_velocity[4] = 10.0;  // 850 W: below, and the clock restarts
  EXPECT_EQ(supervisor.Check(s, 0.02), 0u);
}

TEST(SafetySupervisor, ClampTargetsKeepsEveryJointInItsRange) {
  a1::JointArray<double> q;
  q.fill(10.0);
  q[0] = -10.0;
  q[5] = -1.0;  // FL calf: inside its range, unchanged
  SafetySupervisor::ClampTargets(q);
  EXPECT_DOUBLE_EQ(q[0], a1::JointMin(0));
  EXPECT_DOUBLE_EQ(q[1], a1::JointMax(1));
  EXPECT_DOUBLE_EQ(q[2], a1::JointMax(2));
  EXPECT_DOUBLE_EQ(q[5], -1.0);
}

TEST(DescribeFaults, NamesEachFaultWithItsValue) {
  SafetyConfig config;
  RobotState s = Rolled(1.31);
  s.joint_velocity[10] = 30.0;
  char text[192];
  DescribeFaults(kFaultTilt | kFaultJointVelocity, s, config, text, sizeof text);
  EXPECT_THAT(text, HasSubstr("tilt 1.31 rad > 1.00"));
  EXPECT_THAT(text, HasSubstr("RL_thigh_joint at 30.0 rad/s > 21.0"));
  EXPECT_THAT(text, HasSubstr("; "));
}

TEST(DescribeFaults, TruncatesSafelyIntoASmallBuffer) {
  char text[12];
  DescribeFaults(kFaultTilt | kFaultStop | kFaultBackend, Rolled(2.0), SafetyConfig{}, text, sizeof text);
  EXPECT_EQ(std::string(text).size(), sizeof text - 1);
}

// A simulated episode under TerminationOf ends where the supervisor trips on the same state: a hip
// 0.3 rad out of range, a base below the height limit; a standing robot goes on under both.
TEST(TerminationOf, EndsAnEpisodeWhereTheSupervisorTrips) {
  const SafetyConfig safety;
  EnvConfig config;
  config.randomization.DisableAll();
  config.reset.joint_pos_scale = {1.0, 1.0};
  config.reset.base_velocity = 0.0;
  config.termination = TerminationOf(safety);
  const MjModelPtr model = LoadMjModel(config.model);
  const std::array<float, a1::kNumJoints> zero{};

  Env standing(*model, config, 1);
  SafetySupervisor supervisor(safety);
  for (int t = 0; t < 50; ++t) {
    ASSERT_EQ(standing.Step(zero.data()), Termination::kNone) << "step " << t;
    ASSERT_EQ(supervisor.Check(standing.state(), a1::kControlDt), 0u) << "step " << t;
  }

  Env out_of_range(*model, config, 1);
  out_of_range.data().qpos[out_of_range.index().qpos[0]] = a1::JointMin(0) - 0.3;
  out_of_range.SyncState();
  EXPECT_EQ(out_of_range.Step(zero.data()), Termination::kJointRange);
  EXPECT_TRUE(SafetySupervisor(safety).Check(out_of_range.state(), a1::kControlDt) & kFaultJointRange);

  SafetyConfig tall = safety;
  tall.limits.min_base_height = 0.5;  // above the standing robot
  config.termination = TerminationOf(tall);
  Env low(*model, config, 1);
  EXPECT_EQ(low.Step(zero.data()), Termination::kLowBase);
  EXPECT_TRUE(SafetySupervisor(tall).Check(low.state(), a1::kControlDt) & kFaultLowBase);
}

}  // namespace
}  // namespace flsd
