#pragma once
// Turns a planned path into body-frame velocity commands (vx, vy, wz) for the skill selector:
// pure pursuit of a point `lookahead` metres further along the path, walking towards it (a
// quadruped may step sideways) while turning to face it, and slowing down over the last half
// metre, and to the speed at which max_turn_rate walks the arc through that point. Optionally, far
// off its heading the robot first turns in place (for a library that turns both ways better than
// it steps sideways), and it slows down where little room is left beyond its radius.

#include <Eigen/Core>

#include <cmath>
#include <vector>

#include "core/config.h"

namespace flsd {

struct FollowerConfig {
  double lookahead = 0.6;        // m along the path
  // m/s. Just above the shipped library's fastest forward walk (0.88 m/s), so that the
  // nearest-skill selector picks it on a straight (at 0.8 it picked the 0.72 m/s walk; flsd bench
  // nav: 0.9 took 5 % less time, reaching as many goals).
  double max_speed = 0.9;
  double max_turn_rate = 1.0;    // rad/s (skilld: at most the rate of the library's tightest turn)
  double heading_gain = 1.5;     // rad/s per rad of heading error
  double goal_tolerance = 0.25;  // m from the last waypoint counts as reached
  double replan_distance = 0.75;  // m off the path: plan again
  double turn_in_place_above = M_PI;  // rad of heading error beyond which it only turns (pi: never)
  // Speed scales with the clearance left beyond the robot's radius, down to min_speed_share of
  // max_speed at none (slow_clearance 0: never).
  double slow_clearance = 0.0;  // m
  double min_speed_share = 0.4;
  template <class V>
  void Visit(V& v) {
    v("lookahead", lookahead, Bounds<double>{0.05, 10.0});
    v("max_speed", max_speed, Bounds<double>{0.05, 5.0});
    v("max_turn_rate", max_turn_rate, Bounds<double>{0.05, 10.0});
    v("heading_gain", heading_gain, Bounds<double>{0.0, 100.0});
    v("goal_tolerance", goal_tolerance, Bounds<double>{0.01, 10.0});
    v("replan_distance", replan_distance, Bounds<double>{0.05, 100.0});
    v("turn_in_place_above", turn_in_place_above, Bounds<double>{0.0, 3.15});
    v("slow_clearance", slow_clearance, Bounds<double>{0.0, 10.0});
    v("min_speed_share", min_speed_share, Bounds<double>{0.0, 1.0});
  }
};

struct FollowerCommand {
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // vx, vy (m/s, body frame), wz (rad/s)
  bool reached = false;
  bool off_path = false;
  double distance_to_path = 0.0;  // m
  double remaining = 0.0;         // m along the path to the goal
};

class WaypointFollower {
 public:
  WaypointFollower(std::vector<Eigen::Vector2d> waypoints, const FollowerConfig& config);

  // The command for a robot at `position` (world, m) heading `yaw` (rad), with `free_clearance` m
  // between its radius and the nearest obstacle (Map2D::Clearance minus the robot's radius).
  FollowerCommand Update(const Eigen::Vector2d& position, double yaw, double free_clearance = HUGE_VAL);

 private:
  std::vector<Eigen::Vector2d> waypoints_;
  std::vector<double> arc_;  // path length from the start to each waypoint
  FollowerConfig config_;
  double progress_ = 0.0;  // arc length of the closest point found so far; never goes back
};

}  // namespace flsd
