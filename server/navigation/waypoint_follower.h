#pragma once
// Turns a planned path into body-frame velocity commands (vx, vy, wz) for the skill selector:
// pure pursuit of a point `lookahead` metres further along the path, walking towards it (a
// quadruped may step sideways) while turning to face it, and slowing down over the last half
// metre, and to the speed at which max_turn_rate walks the arc through that point. Optionally, far
// off its heading the robot first turns in place (for a library that turns both ways better than
// it steps sideways), and it slows down where little room is left beyond its radius.
// A library whose fastest gait goes backward (a gallop) is used where that is sooner: the path is
// cut into straight stretches, and on each the follower chooses to face along it or away from it,
// by the time a turn at max_turn_rate and the walk at max_speed or backward_speed take. Facing
// away, it turns in place until its back points at the stretch's end, then walks backward.

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <cstdint>
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
  // m/s at which the robot walks a stretch backward, its back turned along it (0: never).
  double backward_speed = 0.0;
  // rad off the stretch's end, behind the robot, beyond which it turns in place before it walks
  // backward (unless it would pass the end within goal_tolerance anyway).
  double backward_align = 0.15;
  // rad before its back points at the end at which it stops turning: a turn in place runs on
  // after the command changes (about 0.1 rad for the shipped library's, at 1.5-2.5 rad/s).
  double turn_lead = 0.1;
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
    v("backward_speed", backward_speed, Bounds<double>{0.0, 5.0});
    v("backward_align", backward_align, Bounds<double>{0.01, 3.15});
    v("turn_lead", turn_lead, Bounds<double>{0.0, 1.0});
  }
};

struct FollowerCommand {
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // vx, vy (m/s, body frame), wz (rad/s)
  bool reached = false;
  bool off_path = false;
  double distance_to_path = 0.0;  // m
  double remaining = 0.0;         // m along the path to the goal
  bool backward = false;          // walking (or turning to walk) the stretch backward
};

class WaypointFollower {
 public:
  WaypointFollower(std::vector<Eigen::Vector2d> waypoints, const FollowerConfig& config);

  // The command for a robot at `position` (world, m) heading `yaw` (rad), with `free_clearance` m
  // between its radius and the nearest obstacle (Map2D::Clearance minus the robot's radius).
  FollowerCommand Update(const Eigen::Vector2d& position, double yaw, double free_clearance = HUGE_VAL);

  // m every waypoint between a stretch's ends keeps to the straight line between them.
  static constexpr double kStraightTolerance = 0.05;

 private:
  // Whether every waypoint strictly between `first` and `last` lies within kStraightTolerance of
  // the segment between them.
  bool Straight(size_t first, size_t last) const;
  // Chooses the facing for stretch `index` from where the robot stands.
  void Face(size_t index, const Eigen::Vector2d& position, double yaw);

  std::vector<Eigen::Vector2d> waypoints_;
  std::vector<double> arc_;  // path length from the start to each waypoint
  FollowerConfig config_;
  double progress_ = 0.0;  // arc length of the closest point found so far; never goes back
  std::vector<size_t> stretch_ends_;  // waypoint index of each straight stretch's end, in order
  size_t stretch_ = SIZE_MAX;         // the stretch whose facing is chosen
  bool backward_ = false;             // facing away along it
  int turning_ = 0;                   // +1, -1: turning in place that way to walk backward
  bool aligned_ = false;              // done turning for this stretch
};

}  // namespace flsd
