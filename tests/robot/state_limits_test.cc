// StateLimits, the limits skilld stops the robot by and training ends episodes by: each breaks at
// its threshold and not below it, a negative or zero setting turns a check off, and a NaN breaks
// every limit it enters.

#include "robot/state_limits.h"

#include <gtest/gtest.h>

#include <cmath>

#include "robot/robot_state.h"
#include "tests/common/robot_states.h"

namespace flsd {
namespace {

using testutil::Standing;

RobotState Pitched(double angle) { return testutil::Turned(Eigen::Vector3d::UnitY(), angle); }

TEST(TiltOf, IsTheAngleFromUprightWhicheverWay) {
  EXPECT_NEAR(TiltOf(Standing()), 0.0, 1e-12);
  EXPECT_NEAR(TiltOf(Pitched(0.4)), 0.4, 1e-9);
  EXPECT_NEAR(TiltOf(Pitched(-2.9)), 2.9, 1e-9);
  RobotState broken = Standing();
  broken.base_orientation.coeffs().setConstant(NAN);
  EXPECT_TRUE(std::isnan(TiltOf(broken)));
}

TEST(BrokenLimits, EachAtItsThreshold) {
  const StateLimits limits;  // 1.0 rad, 0.12 m, 0.1 rad past the range
  EXPECT_EQ(BrokenLimits(Standing(), limits), 0u);
  EXPECT_EQ(BrokenLimits(Pitched(0.99), limits), 0u);
  EXPECT_EQ(BrokenLimits(Pitched(1.01), limits), kBreaksTilt);
  RobotState low = Standing();
  low.base_position.z() = 0.119;
  EXPECT_EQ(BrokenLimits(low, limits), kBreaksBaseHeight);
  RobotState bent = Standing();
  bent.joint_position[2] = a1::JointMin(2) - 0.09;
  EXPECT_EQ(BrokenLimits(bent, limits), 0u);
  bent.joint_position[2] = a1::JointMin(2) - 0.11;
  EXPECT_EQ(BrokenLimits(bent, limits), kBreaksJointRange);
}

TEST(BrokenLimits, OffSettingsCheckNothing) {
  StateLimits off;
  off.min_base_height = 0.0;
  off.joint_range_margin = -1.0;
  RobotState s = Standing();
  s.base_position.z() = 0.01;
  s.joint_position[2] = a1::JointMin(2) - 1.0;
  EXPECT_EQ(BrokenLimits(s, off), 0u);
}

TEST(BrokenLimits, NaNBreaksWhatItEnters) {
  const StateLimits limits;
  RobotState s = Standing();
  s.base_position.z() = NAN;
  s.joint_position[4] = NAN;
  EXPECT_EQ(BrokenLimits(s, limits), kBreaksBaseHeight | kBreaksJointRange);
}

}  // namespace
}  // namespace flsd
