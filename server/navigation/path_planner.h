#pragma once
// Plans a collision-free path on a Map2D with OMPL: an asymptotically optimal planner (informed
// RRT*) for a fixed time, then OMPL's path simplification, then waypoints no further apart than
// a set spacing, for the follower. A shortest path grazes every obstacle it passes at exactly the
// robot's radius, where a walking robot's sway takes it inside; the planner therefore first keeps
// a margin beyond the radius, and only where no such path is found (a narrow gap) plans without.
// A robot that cannot turn in place (a library whose skills turn only while they walk) is planned
// for with a turning radius: Dubins curves from its heading (dubins.h), which it can
// follow without overshooting; where none is found it gets straight segments, as one that turns
// in place would.

#include <Eigen/Core>

#include <string>
#include <vector>

#include "navigation_map/map2d.h"

namespace flsd {

struct PlannerOptions {
  double time_limit = 0.5;        // s of planning
  double waypoint_spacing = 0.5;  // m, at most, between waypoints
  double collision_resolution = 0.02;  // m along a segment between checks
  bool first_solution_only = false;  // stop at the first path found instead of improving it
  double clearance_margin = 0.0;  // m kept beyond the robot's radius where a path allows it
  double turning_radius = 0.0;  // m: the path turns no tighter (0: straight segments)
};

struct PlannedPath {
  enum class Status { kFound, kStartBlocked, kGoalBlocked, kNoPath };
  Status status = Status::kNoPath;
  std::vector<Eigen::Vector2d> waypoints;  // from the start to the goal, both included
  double length = 0.0;                     // m
  double planning_seconds = 0.0;
  double margin = 0.0;  // m beyond the robot's radius the path keeps (but near its ends)
  double turning_radius = 0.0;  // m the path keeps to; 0 where it is straight segments
  std::string message;  // why, when not found
};
const char* ToString(PlannedPath::Status status);

// `start_yaw` (rad) is the robot's heading, which a path with a turning radius leaves along; the
// goal may be reached at any heading.
PlannedPath PlanPath(const Map2D& map, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                     const PlannerOptions& options = {}, double start_yaw = 0.0);

// The waypoints of a polyline with consecutive points at most `spacing` apart.
std::vector<Eigen::Vector2d> Densify(const std::vector<Eigen::Vector2d>& path, double spacing);

}  // namespace flsd
