#include "server/navigation/path_planner.h"

#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/InformedRRTstar.h>
#include <ompl/util/Console.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

namespace flsd {
namespace {

namespace ob = ompl::base;
namespace og = ompl::geometric;

std::string Where(const Eigen::Vector2d& p) {
  char text[64];
  std::snprintf(text, sizeof text, "(%.2f, %.2f)", p.x(), p.y());
  return text;
}

constexpr double kMaxWayOut = 2.0;  // m a start inside an obstacle may be from its edge

// The point a little outside the obstacle (or inside the map) that a straight walk up the
// clearance's gradient from `p` reaches first, if within kMaxWayOut.
std::optional<Eigen::Vector2d> WayOut(const Map2D& map, Eigen::Vector2d p) {
  constexpr double kStep = 0.02, kOutside = 0.05;  // m
  for (double walked = 0.0; walked <= kMaxWayOut; walked += kStep) {
    if (map.Clearance(p) > kOutside) return p;
    const Eigen::Vector2d dx(kStep, 0.0), dy(0.0, kStep);
    const Eigen::Vector2d gradient(map.Clearance(p + dx) - map.Clearance(p - dx), map.Clearance(p + dy) - map.Clearance(p - dy));
    if (!(gradient.norm() > 0.0)) return std::nullopt;  // a ridge: no way out is better than another
    p += kStep * gradient.normalized();
  }
  return std::nullopt;
}

// The simplified path's corners on `map` with `margin` beyond the robot's radius, or none.
// States near the start need only be outside obstacles (a robot that strayed into the margin
// walks back out), and states near the goal need only be free.
std::optional<std::vector<Eigen::Vector2d>> Solve(const Map2D& map, const Eigen::Vector2d& start,
                                                  const Eigen::Vector2d& goal, const PlannerOptions& options,
                                                  double margin) {
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
  auto space = std::make_shared<ob::RealVectorStateSpace>(2);
  ob::RealVectorBounds bounds(2);
  bounds.setLow(0, map.x_min);
  bounds.setHigh(0, map.x_max);
  bounds.setLow(1, map.y_min);
  bounds.setHigh(1, map.y_max);
  space->setBounds(bounds);
  og::SimpleSetup setup(space);
  const double keep = map.robot_radius + margin;
  setup.setStateValidityChecker([&map, &start, &goal, keep](const ob::State* s) {
    const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
    const Eigen::Vector2d p(v->values[0], v->values[1]);
    const double clearance = map.Clearance(p);
    return clearance >= keep || ((p - start).norm() < keep && clearance > 0.0) ||
           ((p - goal).norm() < keep && clearance >= map.robot_radius);
  });
  const double extent = std::max(map.x_max - map.x_min, map.y_max - map.y_min);
  setup.getSpaceInformation()->setStateValidityCheckingResolution(options.collision_resolution / extent);
  ob::ScopedState<> from(space), to(space);
  from[0] = start.x();
  from[1] = start.y();
  to[0] = goal.x();
  to[1] = goal.y();
  setup.setStartAndGoalStates(from, to);
  auto objective = std::make_shared<ob::PathLengthOptimizationObjective>(setup.getSpaceInformation());
  // The planner stops once a path is within 1 % of the straight line, which no path can beat (an
  // open room then takes a millisecond, not the whole budget); an infinite threshold is met by
  // any path, so the planner stops at its first one.
  objective->setCostThreshold(ob::Cost(options.first_solution_only ? std::numeric_limits<double>::infinity()
                                                                   : 1.01 * (goal - start).norm()));
  setup.getProblemDefinition()->setOptimizationObjective(objective);
  setup.setPlanner(std::make_shared<og::InformedRRTstar>(setup.getSpaceInformation()));

  if (setup.solve(options.time_limit) != ob::PlannerStatus::EXACT_SOLUTION) return std::nullopt;
  setup.simplifySolution();
  const og::PathGeometric& path = setup.getSolutionPath();
  std::vector<Eigen::Vector2d> corners;
  for (std::size_t i = 0; i < path.getStateCount(); ++i) {
    const auto* v = path.getState(i)->as<ob::RealVectorStateSpace::StateType>();
    corners.emplace_back(v->values[0], v->values[1]);
  }
  return corners;
}

}  // namespace

const char* ToString(PlannedPath::Status status) {
  switch (status) {
    case PlannedPath::Status::kFound: return "found";
    case PlannedPath::Status::kStartBlocked: return "start blocked";
    case PlannedPath::Status::kGoalBlocked: return "goal blocked";
    case PlannedPath::Status::kNoPath: return "no path";
  }
  return "unknown";
}

std::vector<Eigen::Vector2d> Densify(const std::vector<Eigen::Vector2d>& path, double spacing) {
  std::vector<Eigen::Vector2d> out;
  if (path.empty()) return out;
  out.push_back(path.front());
  for (size_t i = 1; i < path.size(); ++i) {
    const Eigen::Vector2d step = path[i] - path[i - 1];
    const int pieces = std::max(1, static_cast<int>(std::ceil(step.norm() / spacing)));
    for (int k = 1; k <= pieces; ++k) out.push_back(path[i - 1] + step * (static_cast<double>(k) / pieces));
  }
  return out;
}

PlannedPath PlanPath(const Map2D& map, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                     const PlannerOptions& options) {
  PlannedPath result;
  const auto begin = std::chrono::steady_clock::now();
  // A robot that has strayed into the margin around an obstacle or the map's edge (a replan after
  // an overshoot) may still walk out of it: states within the robot's radius of the start need
  // only be outside obstacles (Solve). One whose centre is inside an obstacle (the map's obstacles
  // need not exist in the world) is led straight out, up the clearance's gradient, and planned
  // for from there.
  Eigen::Vector2d from = start;
  if (!(map.Clearance(start) > 0.0)) {
    const std::optional<Eigen::Vector2d> exit = WayOut(map, start);
    if (!exit) {
      char text[160];
      std::snprintf(text, sizeof text, "the start %s is inside an obstacle or off the map, more than %.1f m from its edge",
                    Where(start).c_str(), kMaxWayOut);
      result.status = PlannedPath::Status::kStartBlocked;
      result.message = text;
      return result;
    }
    from = *exit;
  }
  if (!map.IsFree(goal)) {
    result.status = PlannedPath::Status::kGoalBlocked;
    result.message = "the goal " + Where(goal) + " is within the robot's radius of an obstacle or the map's edge";
    return result;
  }

  for (const double margin : {options.clearance_margin, 0.0}) {
    std::optional<std::vector<Eigen::Vector2d>> corners = Solve(map, from, goal, options, margin);
    if (corners) {
      if (from != start) corners->insert(corners->begin(), start);
      result.status = PlannedPath::Status::kFound;
      result.margin = margin;
      result.length = 0.0;
      for (size_t i = 1; i < corners->size(); ++i) result.length += ((*corners)[i] - (*corners)[i - 1]).norm();
      result.waypoints = Densify(*corners, options.waypoint_spacing);
      break;
    }
    if (margin == 0.0) {
      result.status = PlannedPath::Status::kNoPath;
      result.message = "no collision-free path from " + Where(start) + " to " + Where(goal) + " found in " +
                       std::to_string(options.time_limit) + " s";
      break;
    }
  }
  result.planning_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return result;
}

}  // namespace flsd
