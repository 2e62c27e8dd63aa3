// legged_gym's velocity-tracking reward against hand-computed values, term by term.

#include "skills/learning/tasks/velocity_tracking.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;

constexpr double kDt = a1::kControlDt;

RobotState Standing() {
  RobotState s;
  s.base_position = {0.0, 0.0, 0.27};
  s.joint_position = a1::kDefaultJointPos;
  s.foot_contact = {true, true, true, true};
  return s;
}

// Only the named term's scale left on.
VelocityRewardConfig Only(double VelocityRewardConfig::*term) {
  VelocityRewardConfig c;
  for (double VelocityRewardConfig::*t :
       {&VelocityRewardConfig::tracking_lin_vel, &VelocityRewardConfig::tracking_ang_vel, &VelocityRewardConfig::lin_vel_z,
        &VelocityRewardConfig::ang_vel_xy, &VelocityRewardConfig::orientation, &VelocityRewardConfig::torques,
        &VelocityRewardConfig::dof_acc, &VelocityRewardConfig::feet_air_time, &VelocityRewardConfig::collision,
        &VelocityRewardConfig::action_rate, &VelocityRewardConfig::dof_pos_limits}) {
    if (t != term) c.*t = 0.0;
  }
  return c;
}

const float kZeroAction[a1::kNumJoints] = {};

TEST(VelocityTrackingReward, PerfectTrackingAtRestEarnsBothTrackingTerms) {
  VelocityTrackingReward reward{VelocityRewardConfig{}};
  reward.Reset(Standing());
  const VelocityRewardTerms t = reward.Step(Standing(), Eigen::Vector3d::Zero(), kZeroAction, false);
  EXPECT_DOUBLE_EQ(t.tracking_lin_vel, 1.0);
  EXPECT_DOUBLE_EQ(t.tracking_ang_vel, 1.0);
  EXPECT_NEAR(t.total, (1.0 + 0.5) * kDt, 1e-12);
}

TEST(VelocityTrackingReward, TrackingDecaysWithTheSquaredError) {
  VelocityTrackingReward reward{Only(&VelocityRewardConfig::tracking_lin_vel)};
  RobotState s = Standing();
  reward.Reset(s);
  s.base_linear_velocity = {0.3, 0.4, 0.0};  // 0.5 m/s off a zero command
  const VelocityRewardTerms t = reward.Step(s, Eigen::Vector3d::Zero(), kZeroAction, false);
  EXPECT_NEAR(t.tracking_lin_vel, std::exp(-0.25 / 0.25), 1e-12);
  EXPECT_NEAR(t.total, std::exp(-1.0) * kDt, 1e-12);
}

TEST(VelocityTrackingReward, PenaltiesSubtractAndTheTotalIsClippedAtZero) {
  VelocityRewardConfig config = Only(&VelocityRewardConfig::tracking_lin_vel);
  config.lin_vel_z = -2.0;
  VelocityTrackingReward reward(config);
  RobotState s = Standing();
  reward.Reset(s);
  s.base_linear_velocity = {0.0, 0.0, 0.5};  // tracking 1.0, lin_vel_z 0.25 -> 1 - 0.5
  EXPECT_NEAR(reward.Step(s, Eigen::Vector3d::Zero(), kZeroAction, false).total, 0.5 * kDt, 1e-12);
  s.base_linear_velocity = {0.0, 0.0, 1.0};  // 1 - 2 < 0: clipped
  EXPECT_EQ(reward.Step(s, Eigen::Vector3d::Zero(), kZeroAction, false).total, 0.0);
}

TEST(VelocityTrackingReward, ScaledTermsSumToTheUnclippedRewardPerSecond) {
  VelocityRewardConfig config = Only(&VelocityRewardConfig::tracking_lin_vel);
  config.lin_vel_z = -2.0;
  VelocityTrackingReward reward(config);
  RobotState s = Standing();
  reward.Reset(s);
  s.base_linear_velocity = {0.0, 0.0, 1.0};  // tracking 1.0, lin_vel_z 1.0 -> 1 - 2
  const VelocityRewardTerms raw = reward.Step(s, Eigen::Vector3d::Zero(), kZeroAction, false);
  const VelocityRewardTerms scaled = Scaled(raw, config);
  EXPECT_DOUBLE_EQ(scaled.tracking_lin_vel, 1.0);
  EXPECT_DOUBLE_EQ(scaled.lin_vel_z, -2.0);
  EXPECT_DOUBLE_EQ(scaled.tracking_ang_vel, 0.0);  // scale 0
  EXPECT_DOUBLE_EQ(scaled.total, -1.0);            // per second, not clipped
  EXPECT_EQ(raw.total, 0.0);                       // the step's reward is
}

TEST(VelocityTrackingReward, FeetAirTimeIsPaidAtTouchdownWhileMoving) {
  VelocityTrackingReward reward{Only(&VelocityRewardConfig::feet_air_time)};
  RobotState s = Standing();
  reward.Reset(s);
  const Eigen::Vector3d walk(0.5, 0.0, 0.0);
  s.foot_contact[0] = false;
  reward.Step(s, walk, kZeroAction, false);  // the filter still sees last step's contact
  for (int i = 0; i < 34; ++i) EXPECT_EQ(reward.Step(s, walk, kZeroAction, false).feet_air_time, 0.0);
  s.foot_contact[0] = true;
  // The air time counts the 34 steps after the filtered one, and the touchdown step: 0.70 s.
  const VelocityRewardTerms t = reward.Step(s, walk, kZeroAction, false);
  EXPECT_NEAR(t.feet_air_time, 0.70 - 0.5, 1e-9);
  EXPECT_EQ(reward.Step(s, walk, kZeroAction, false).feet_air_time, 0.0);  // no second payment
}

TEST(VelocityTrackingReward, SoftJointLimitsAndActionRate) {
  VelocityRewardConfig config = Only(&VelocityRewardConfig::dof_pos_limits);
  VelocityTrackingReward reward(config);
  RobotState s = Standing();
  reward.Reset(s);
  // The hip's soft limit is 0.9 of +-0.802851: 0.722566; 0.8 is 0.077434 beyond it.
  s.joint_position[0] = 0.8;
  float action[a1::kNumJoints] = {};
  action[5] = 2.0f;
  const VelocityRewardTerms t = reward.Step(s, Eigen::Vector3d::Zero(), action, false);
  EXPECT_NEAR(t.dof_pos_limits, 0.8 - 0.9 * 0.802851, 1e-9);
  EXPECT_NEAR(t.action_rate, 4.0, 1e-12);
}

TEST(SampleVelocityCommand, StaysInItsRangesAndZeroesSlowPlanarCommands) {
  VelocityCommandConfig config;
  Rng rng(5);
  int zeroed = 0;
  for (int i = 0; i < 10000; ++i) {
    const Eigen::Vector3d c = SampleVelocityCommand(rng, config);
    ASSERT_LE(c.cwiseAbs().maxCoeff(), 1.0);
    if (c.head<2>().isZero()) {
      ++zeroed;
    } else {
      ASSERT_GE(c.head<2>().norm(), 0.2);
    }
  }
  // The disc of radius 0.2 covers pi 0.04 / 4 of the square: about 3.1 %.
  EXPECT_NEAR(zeroed / 10000.0, M_PI * 0.04 / 4.0, 0.006);
}

// Half the commands near one of two skills (+-0.1 m/s, +-0.2 rad/s), the rest uniform in the
// ranges; a skill share without skill velocities in triples is refused.
TEST(SampleVelocityCommand, DrawsItsSkillShareNearTheSkillsVelocities) {
  VelocityCommandConfig config;
  config.skill_share = 0.5;
  config.skill_noise = {0.1, 0.1, 0.2};
  config.skill_velocities = {0.5, 0.0, 0.0, -0.1, 0.6, 0.8};
  config.min_planar_speed = 0.0;
  ValidateSkillCommands(config);
  Rng rng(9);
  int near[2] = {0, 0};
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d c = SampleVelocityCommand(rng, config);
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3d v(&config.skill_velocities[3 * k]);
      near[k] += std::abs(c.x() - v.x()) <= 0.1 && std::abs(c.y() - v.y()) <= 0.1 && std::abs(c.z() - v.z()) <= 0.2;
    }
  }
  // Each skill gets a quarter of the draws, plus the uniform draws that land in its box (0.2 x 0.2
  // x 0.4 of the 2 x 2 x 2 box: 0.2 % of the other half).
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(near[k] / double(n), 0.25 + 0.5 * 0.002, 0.01) << "skill " << k;
  config.skill_velocities = {0.5, 0.0};
  EXPECT_THAT(testutil::InputErrorMessage([&] { ValidateSkillCommands(config); }), HasSubstr("triples"));
}

}  // namespace
}  // namespace flsd
