// Dubins paths with known answers (a straight line, a half circle, turning around) and, for many
// random pose pairs, a round trip: walking the path from the start ends at the goal pose, no piece
// jumps, and no path is shorter than the straight line.

#include "server/navigation/dubins.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace flsd {
namespace {

using Turn = DubinsPath::Turn;

double AngleBetween(double a, double b) { return std::abs(std::remainder(a - b, 2.0 * M_PI)); }

TEST(DubinsPath, AheadIsTheStraightLine) {
  const DubinsPath path({0.0, 0.0, 0.0}, {2.0, 0.0, 0.0}, 0.5);
  EXPECT_NEAR(path.length(), 2.0, 1e-12);
  const Pose2 half = path.At(1.0);
  EXPECT_NEAR(half.x, 1.0, 1e-12);
  EXPECT_NEAR(half.y, 0.0, 1e-12);
}

// (0, 2r) facing back is the top of the left turning circle: half of it, pi r.
TEST(DubinsPath, ThePoseAcrossTheLeftCircleIsHalfOfIt) {
  const DubinsPath path({0.0, 0.0, 0.0}, {0.0, 1.2, M_PI}, 0.6);
  EXPECT_NEAR(path.length(), 0.6 * M_PI, 1e-9);
  EXPECT_EQ(path.word()[0], Turn::kLeft);
  const Pose2 quarter = path.At(0.3 * M_PI);  // a quarter of the circle: (r, r), facing +y
  EXPECT_NEAR(quarter.x, 0.6, 1e-9);
  EXPECT_NEAR(quarter.y, 0.6, 1e-9);
  EXPECT_NEAR(quarter.yaw, M_PI / 2, 1e-9);
}

// The same pose 1 m behind, facing the same way: no arc of radius 1 reverses, so the path turns
// away and back (longer than the 1 m straight line by far), and it ends where it should.
TEST(DubinsPath, APoseBehindIsReachedByTurningAround) {
  const DubinsPath path({0.0, 0.0, 0.0}, {-1.0, 0.0, 0.0}, 1.0);
  EXPECT_GT(path.length(), 2.0 * M_PI);
  const Pose2 end = path.At(path.length());
  EXPECT_NEAR(end.x, -1.0, 1e-9);
  EXPECT_NEAR(end.y, 0.0, 1e-9);
  EXPECT_NEAR(AngleBetween(end.yaw, 0.0), 0.0, 1e-9);
}

TEST(DubinsPath, EveryRandomPathEndsAtItsGoalWithoutJumping) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> position(-3.0, 3.0), yaw(-M_PI, M_PI), radius(0.2, 1.5);
  for (int i = 0; i < 2000; ++i) {
    const Pose2 from{position(rng), position(rng), yaw(rng)}, to{position(rng), position(rng), yaw(rng)};
    const double r = radius(rng);
    const DubinsPath path(from, to, r);
    ASSERT_GE(path.length(), std::hypot(to.x - from.x, to.y - from.y) - 1e-9) << i;
    ASSERT_LE(path.length(), std::hypot(to.x - from.x, to.y - from.y) + 4.0 * M_PI * r) << i;
    const Pose2 end = path.At(path.length());
    ASSERT_NEAR(end.x, to.x, 1e-7) << i;
    ASSERT_NEAR(end.y, to.y, 1e-7) << i;
    ASSERT_NEAR(AngleBetween(end.yaw, to.yaw), 0.0, 1e-7) << i;
    constexpr double kStep = 0.01;
    Pose2 previous = from;
    for (double s = kStep; s < path.length(); s += kStep) {
      const Pose2 p = path.At(s);
      ASSERT_LE(std::hypot(p.x - previous.x, p.y - previous.y), kStep + 1e-9) << i << " at " << s;
      previous = p;
    }
  }
}

}  // namespace
}  // namespace flsd
