#include "robot/joint_limit_timer.h"

#include <gtest/gtest.h>

#include <limits>

namespace flsd {
namespace {

TEST(JointLimitTimer, TimesEachJointsUnbrokenStretchAndClearsItWhenTheJointComesBack) {
  JointLimitTimer timer;
  a1::JointArray<double> qd{};
  const auto fast = FasterThan(qd, 21.0);
  qd[2] = 22.0;
  EXPECT_DOUBLE_EQ(timer.Update(fast, 0.02), 0.02);
  qd[5] = -30.0;  // a second joint starts later and in the other direction
  EXPECT_DOUBLE_EQ(timer.Update(fast, 0.02), 0.04);
  qd[2] = 21.0;  // at the limit is not past it
  EXPECT_DOUBLE_EQ(timer.Update(fast, 0.02), 0.04);  // joint 5's two ticks
  qd[5] = 0.0;
  EXPECT_DOUBLE_EQ(timer.Update(fast, 0.02), 0.0);
  qd[7] = std::numeric_limits<double>::quiet_NaN();  // an unreadable speed counts as too fast
  EXPECT_DOUBLE_EQ(timer.Update(fast, 0.02), 0.02);
  timer.Reset();
  EXPECT_DOUBLE_EQ(timer.Longest(), 0.0);
  qd[7] = 0.0;
  EXPECT_DOUBLE_EQ(timer.Update(fast, 0.02), 0.0);
}

TEST(JointLimitTimer, OutlastsOnlyPastTheToleranceThoughTicksSumInexactly) {
  JointLimitTimer timer;
  const auto always = [](int) { return true; };
  double held = 0.0;
  for (int tick = 0; tick < 2; ++tick) held = timer.Update(always, 0.02);
  EXPECT_FALSE(Outlasts(held, 0.04));  // two 20 ms ticks are 0.04 s, not more
  held = timer.Update(always, 0.02);
  EXPECT_TRUE(Outlasts(held, 0.04));
  EXPECT_TRUE(Outlasts(0.02, 0.0));
  EXPECT_FALSE(Outlasts(0.0, 0.0));
}

}  // namespace
}  // namespace flsd
