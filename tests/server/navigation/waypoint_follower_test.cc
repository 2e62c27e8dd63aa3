// The follower's commands for robots placed by hand along a known path.

#include "server/navigation/waypoint_follower.h"

#include <gtest/gtest.h>

#include <cmath>

namespace flsd {
namespace {

const std::vector<Eigen::Vector2d> kStraight = {{0, 0}, {1, 0}, {2, 0}, {3, 0}};

// The defaults with a top speed of 0.5 m/s, which the known answers below are worked out for.
FollowerConfig HalfMetrePerSecond() {
  FollowerConfig config;
  config.max_speed = 0.5;
  return config;
}

TEST(WaypointFollower, WalksForwardAlongAStraightPathItFaces) {
  WaypointFollower follower(kStraight, HalfMetrePerSecond());
  const FollowerCommand c = follower.Update({0.0, 0.0}, 0.0);
  EXPECT_NEAR(c.velocity.x(), 0.5, 1e-9);
  EXPECT_NEAR(c.velocity.y(), 0.0, 1e-9);
  EXPECT_NEAR(c.velocity.z(), 0.0, 1e-9);
  EXPECT_FALSE(c.reached);
  EXPECT_NEAR(c.remaining, 3.0, 1e-9);
}

TEST(WaypointFollower, TurnsTowardsAPathToItsLeft) {
  WaypointFollower follower(kStraight, HalfMetrePerSecond());
  const FollowerCommand c = follower.Update({0.0, 0.0}, -M_PI / 2);  // facing -y: the path is to its left
  // It steps left, towards the path, and turns left at the rate limit; the arc through the point
  // 0.6 m to its left has a radius of 0.3 m, which 1 rad/s walks at 0.3 m/s.
  EXPECT_NEAR(c.velocity.x(), 0.0, 1e-9);
  EXPECT_NEAR(c.velocity.y(), 0.3, 1e-9);
  EXPECT_NEAR(c.velocity.z(), 1.0, 1e-9);
}

TEST(WaypointFollower, CanTurnInPlaceTowardsAPathFarOffItsHeadingThenWalk) {
  FollowerConfig config = HalfMetrePerSecond();
  config.turn_in_place_above = 0.8;
  WaypointFollower follower(kStraight, config);
  const FollowerCommand c = follower.Update({0.0, 0.0}, -M_PI / 2);
  EXPECT_EQ(c.velocity.head<2>(), Eigen::Vector2d::Zero());  // it does not walk yet
  EXPECT_NEAR(c.velocity.z(), 1.0, 1e-9);                    // it turns left, at the rate limit
  // 0.5 rad off: it walks towards the lookahead point and turns at 1.5 rad/s per rad.
  const FollowerCommand walking = follower.Update({0.0, 0.0}, -0.5);
  EXPECT_NEAR(walking.velocity.head<2>().norm(), 0.5, 1e-9);
  EXPECT_NEAR(walking.velocity.z(), 0.75, 1e-9);
}

TEST(WaypointFollower, CanSlowDownWhereLittleRoomIsLeftBeyondItsRadius) {
  FollowerConfig config = HalfMetrePerSecond();
  config.slow_clearance = 0.4;
  WaypointFollower follower(kStraight, config);
  // slow_clearance 0.4 m, min_speed_share 0.4: 0.2 m of room leaves 70 % of 0.5 m/s, none 40 %.
  EXPECT_NEAR(follower.Update({0.0, 0.0}, 0.0, 0.2).velocity.x(), 0.35, 1e-9);
  EXPECT_NEAR(follower.Update({0.0, 0.0}, 0.0, 0.0).velocity.x(), 0.2, 1e-9);
  EXPECT_NEAR(follower.Update({0.0, 0.0}, 0.0, 1.0).velocity.x(), 0.5, 1e-9);
}

TEST(WaypointFollower, SteersBackOntoThePathAndSaysWhenItIsTooFarOff) {
  WaypointFollower follower(kStraight, HalfMetrePerSecond());
  const FollowerCommand near = follower.Update({1.0, 0.3}, 0.0);
  EXPECT_LT(near.velocity.y(), 0.0);  // back towards y = 0
  EXPECT_FALSE(near.off_path);
  EXPECT_NEAR(near.distance_to_path, 0.3, 1e-9);
  EXPECT_TRUE(follower.Update({1.0, 1.0}, 0.0).off_path);
}

TEST(WaypointFollower, SlowsDownAndStopsAtTheGoal) {
  WaypointFollower follower(kStraight, HalfMetrePerSecond());
  follower.Update({2.0, 0.0}, 0.0);
  const FollowerCommand close = follower.Update({2.6, 0.0}, 0.0);
  EXPECT_NEAR(close.velocity.x(), 0.5 * 0.4 / 0.5, 1e-9);
  const FollowerCommand done = follower.Update({2.9, 0.05}, 0.0);
  EXPECT_TRUE(done.reached);
  EXPECT_EQ(done.velocity, Eigen::Vector3d::Zero());
}

TEST(WaypointFollower, NeverGoesBackAlongALoopedPath) {
  // Out along y = 0 and back along y = 0.2: near the start, the return leg is what is left.
  WaypointFollower follower({{0, 0}, {2, 0}, {2, 0.2}, {0, 0.2}}, FollowerConfig{});
  follower.Update({1.0, 0.0}, 0.0);
  follower.Update({2.0, 0.1}, M_PI / 2);
  const FollowerCommand back = follower.Update({1.0, 0.2}, M_PI);
  EXPECT_GT(back.velocity.x(), 0.0);  // facing -x, it keeps walking forward, towards x = 0
  EXPECT_NEAR(back.remaining, 1.0, 0.05);
}

}  // namespace
}  // namespace flsd
