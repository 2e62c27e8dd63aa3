// legged_gym's smoothness terms, by hand.

#include "skills/learning/tasks/smoothness.h"

#include <gtest/gtest.h>

#include <array>

#include "robot/a1.h"

namespace flsd {
namespace {

TEST(Smoothness, ActionRateIsTheSquaredChangeOverTheJoints) {
  std::array<float, a1::kNumJoints> action{}, previous{};
  action[0] = 0.5f;
  previous[11] = -2.0f;
  EXPECT_DOUBLE_EQ(ActionRate(action.data(), previous.data()), 0.25 + 4.0);
  EXPECT_DOUBLE_EQ(ActionRate(action.data(), action.data()), 0.0);
}

TEST(Smoothness, JointAccelerationIsTheSquaredChangeOfSpeedOverTheControlStep) {
  std::array<double, a1::kNumJoints> speed{}, previous{};
  speed[3] = 0.1;  // 0.1 rad/s more in one 20 ms step: 5 rad/s^2
  previous[4] = 0.2;  // 0.2 rad/s less: 10 rad/s^2
  EXPECT_NEAR(JointAcceleration(speed.data(), previous.data()), 25.0 + 100.0, 1e-9);
}

}  // namespace
}  // namespace flsd
