#include "server/navigation/path_planner.h"

#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/goals/GoalSampleableRegion.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/rrt/InformedRRTstar.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/RandomNumbers.h>
#include <ompl/util/Console.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "server/navigation/dubins.h"

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

constexpr double kCurveStep = 0.05;  // m between the waypoints that trace a curved path
constexpr double kGoalReach = 0.05;  // m from the goal at which a curved path may end
constexpr double kGuideSpacing = 0.3;  // m between the points of a straight path that curves pass

Eigen::Vector2d PositionOf(const ob::State* s, bool curved) {
  if (curved) {
    const auto* pose = s->as<ob::SE2StateSpace::StateType>();
    return {pose->getX(), pose->getY()};
  }
  const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
  return {v->values[0], v->values[1]};
}

// Poses joined by Dubins paths (server/navigation/dubins.h): distance is their length, and
// interpolation walks them. Collision checks are spaced along that length (SE2's default spaces
// them by the straight distance, too sparse on a path that turns around).
class DubinsSpace : public ob::SE2StateSpace {
 public:
  explicit DubinsSpace(double radius) : radius_(radius) {}
  bool isMetricSpace() const override { return false; }
  bool hasSymmetricDistance() const override { return false; }
  bool hasSymmetricInterpolate() const override { return false; }
  double distance(const ob::State* a, const ob::State* b) const override { return Path(a, b).length(); }
  void interpolate(const ob::State* from, const ob::State* to, double t, ob::State* state) const override {
    const DubinsPath path = Path(from, to);
    const Pose2 pose = path.At(t * path.length());
    auto* out = state->as<StateType>();
    out->setXY(pose.x, pose.y);
    out->setYaw(std::remainder(pose.yaw, 2.0 * M_PI));
  }
  unsigned int validSegmentCount(const ob::State* a, const ob::State* b) const override {
    return ob::StateSpace::validSegmentCount(a, b);
  }
  void sanityChecks() const override {
    ob::StateSpace::sanityChecks(std::numeric_limits<double>::epsilon(), std::numeric_limits<float>::epsilon(),
                                 ~(ob::StateSpace::STATESPACE_INTERPOLATION | ob::StateSpace::STATESPACE_TRIANGLE_INEQUALITY |
                                   ob::StateSpace::STATESPACE_DISTANCE_BOUND | ob::StateSpace::STATESPACE_DISTANCE_SYMMETRIC));
  }

 private:
  DubinsPath Path(const ob::State* a, const ob::State* b) const {
    const auto* p = a->as<StateType>();
    const auto* q = b->as<StateType>();
    return DubinsPath({p->getX(), p->getY(), p->getYaw()}, {q->getX(), q->getY(), q->getYaw()}, radius_);
  }
  double radius_;
};

// The goal of a curved plan: its position, at any heading.
class GoalPosition : public ob::GoalSampleableRegion {
 public:
  GoalPosition(const ob::SpaceInformationPtr& si, const Eigen::Vector2d& goal) : ob::GoalSampleableRegion(si), goal_(goal) {
    setThreshold(kGoalReach);
  }
  double distanceGoal(const ob::State* s) const override { return (PositionOf(s, true) - goal_).norm(); }
  void sampleGoal(ob::State* s) const override {
    auto* pose = s->as<ob::SE2StateSpace::StateType>();
    pose->setXY(goal_.x(), goal_.y());
    pose->setYaw(rng_.uniformReal(-M_PI, M_PI));
  }
  unsigned int maxSampleCount() const override { return std::numeric_limits<unsigned int>::max(); }

 private:
  Eigen::Vector2d goal_;
  mutable ompl::RNG rng_;
};

double PolylineLength(const std::vector<Eigen::Vector2d>& points) {
  double length = 0.0;
  for (size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

// Points at most kCurveStep apart along a path of Dubins curves, each curve divided on its own:
// PathGeometric::interpolate(count) shares the points out over the curves by length and rounds, so a
// short curve could get points 10 cm apart, whose chords cut 2 mm inside a 0.6 m turn.
std::vector<Eigen::Vector2d> PointsAlong(const og::PathGeometric& path) {
  const ob::SpaceInformationPtr& si = path.getSpaceInformation();
  ob::State* between = si->allocState();
  std::vector<Eigen::Vector2d> points{PositionOf(path.getState(0), true)};
  for (std::size_t i = 1; i < path.getStateCount(); ++i) {
    const ob::State* from = path.getState(i - 1);
    const ob::State* to = path.getState(i);
    const int pieces = std::max(1, static_cast<int>(std::ceil(si->distance(from, to) / kCurveStep)));
    for (int k = 1; k < pieces; ++k) {
      si->getStateSpace()->interpolate(from, to, static_cast<double>(k) / pieces, between);
      points.push_back(PositionOf(between, true));
    }
    points.push_back(PositionOf(to, true));
  }
  si->freeState(between);
  return points;
}

// In the open, the shortest free Dubins curve to the goal at one of kGoalHeadings headings is the
// path, found without a search (as a straight line needs none).
std::optional<og::PathGeometric> DirectCurve(const ob::SpaceInformationPtr& si, const ob::ScopedState<>& from,
                                             const Eigen::Vector2d& goal) {
  constexpr int kGoalHeadings = 36;
  std::vector<std::pair<double, ob::ScopedState<>>> ends;
  for (int k = 0; k < kGoalHeadings; ++k) {
    ob::ScopedState<> to(si->getStateSpace());
    to[0] = goal.x();
    to[1] = goal.y();
    to[2] = -M_PI + 2.0 * M_PI * k / kGoalHeadings;
    ends.emplace_back(si->distance(from.get(), to.get()), to);
  }
  std::sort(ends.begin(), ends.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [length, to] : ends) {
    if (si->isValid(to.get()) && si->checkMotion(from.get(), to.get())) return og::PathGeometric(si, from.get(), to.get());
  }
  return std::nullopt;
}

// Dubins curves through the points of a straight-segment path (`guide`, kGuideSpacing apart),
// leaving the start along its heading, passing points along the bisector of their two segments,
// and reaching the goal at whichever heading is shortest; a point that no curve reaches from the
// last one without a loop is skipped, if the next is within two turning radii. Then shortened
// where a curve can skip points. A near-shortest path where the straight one leaves room to turn
// (not through a gap narrower than the turn); none where a curve is blocked.
std::optional<og::PathGeometric> CurvesThrough(const ob::SpaceInformationPtr& si, const ob::ScopedState<>& from,
                                               const std::vector<Eigen::Vector2d>& guide, double turning_radius) {
  if (guide.size() < 2) return std::nullopt;
  const std::vector<Eigen::Vector2d> points = Densify(guide, kGuideSpacing);
  og::PathGeometric path(si, from.get());
  ob::ScopedState<> last = from;
  Eigen::Vector2d last_point = points.front();
  for (size_t i = 1; i + 1 < points.size(); ++i) {
    const Eigen::Vector2d direction =
        (points[i] - points[i - 1]).normalized() + (points[i + 1] - points[i]).normalized();
    ob::ScopedState<> at(si->getStateSpace());
    at[0] = points[i].x();
    at[1] = points[i].y();
    at[2] = std::atan2(direction.y(), direction.x());
    const bool loops = si->distance(last.get(), at.get()) > (points[i] - last_point).norm() + turning_radius;
    if (!loops && si->isValid(at.get()) && si->checkMotion(last.get(), at.get())) {
      path.append(at.get());
      last = at;
      last_point = points[i];
    } else if ((points[i + 1] - last_point).norm() > 2.0 * turning_radius) {
      return std::nullopt;
    }
  }
  std::optional<og::PathGeometric> end = DirectCurve(si, last, points.back());
  if (!end) return std::nullopt;
  path.append(*end);
  og::PathSimplifier simplifier(si);
  simplifier.reduceVertices(path);
  simplifier.shortcutPath(path);
  return path;
}

// The path's waypoints on `map` with `margin` beyond the robot's radius, or none: the simplified
// path's corners, or with a turning radius, points along its curves: a direct curve in the open,
// else curves through the points of `guide` (the straight-segment path), else RRT*'s. States near
// the start need only be outside obstacles (a robot that strayed into the margin walks back out),
// and states near the goal need only be free.
std::optional<std::vector<Eigen::Vector2d>> Solve(const Map2D& map, const Eigen::Vector2d& start, double start_yaw,
                                                  const Eigen::Vector2d& goal, const PlannerOptions& options,
                                                  double margin, double turning_radius,
                                                  const std::vector<Eigen::Vector2d>& guide = {}) {
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
  const bool curved = turning_radius > 0.0;
  ob::RealVectorBounds bounds(2);
  bounds.setLow(0, map.x_min);
  bounds.setHigh(0, map.x_max);
  bounds.setLow(1, map.y_min);
  bounds.setHigh(1, map.y_max);
  ob::StateSpacePtr space;
  if (curved) {
    auto dubins = std::make_shared<DubinsSpace>(turning_radius);
    dubins->setBounds(bounds);
    space = dubins;
  } else {
    auto plane = std::make_shared<ob::RealVectorStateSpace>(2);
    plane->setBounds(bounds);
    space = plane;
  }
  og::SimpleSetup setup(space);
  const double keep = map.robot_radius + margin;
  setup.setStateValidityChecker([&map, &start, &goal, keep, curved](const ob::State* s) {
    const Eigen::Vector2d p = PositionOf(s, curved);
    const double clearance = map.Clearance(p);
    return clearance >= keep || ((p - start).norm() < keep && clearance > 0.0) ||
           ((p - goal).norm() < keep && clearance >= map.robot_radius);
  });
  const ob::SpaceInformationPtr& si = setup.getSpaceInformation();
  si->setStateValidityCheckingResolution(options.collision_resolution / space->getMaximumExtent());
  ob::ScopedState<> from(space);
  from[0] = start.x();
  from[1] = start.y();
  if (curved) {
    from[2] = start_yaw;
    si->setup();  // the motion validator, at the resolution above
    if (std::optional<og::PathGeometric> direct = DirectCurve(si, from, goal)) return PointsAlong(*direct);
    if (std::optional<og::PathGeometric> through = CurvesThrough(si, from, guide, turning_radius)) {
      return PointsAlong(*through);
    }
    setup.setStartState(from);
    setup.setGoal(std::make_shared<GoalPosition>(si, goal));
  } else {
    ob::ScopedState<> to(space);
    to[0] = goal.x();
    to[1] = goal.y();
    setup.setStartAndGoalStates(from, to);
  }
  auto objective = std::make_shared<ob::PathLengthOptimizationObjective>(si);
  // The planner stops once a path is within 1 % of the straight line, which no path can beat (an
  // open room then takes a millisecond, not the whole budget); an infinite threshold is met by
  // any path, so the planner stops at its first one.
  objective->setCostThreshold(ob::Cost(options.first_solution_only ? std::numeric_limits<double>::infinity()
                                                                   : 1.01 * (goal - start).norm()));
  setup.getProblemDefinition()->setOptimizationObjective(objective);
  // Informed sampling needs a straight-line metric; on Dubins curves, plain RRT*. Its warning that
  // Dubins distances are not symmetric is silenced: it checks each motion in the direction walked,
  // so its paths are valid, though only near-shortest.
  if (curved) {
    setup.setPlanner(std::make_shared<og::RRTstar>(si));
    ompl::msg::setLogLevel(ompl::msg::LOG_ERROR);
  } else {
    setup.setPlanner(std::make_shared<og::InformedRRTstar>(si));
  }

  if (setup.solve(options.time_limit) != ob::PlannerStatus::EXACT_SOLUTION) return std::nullopt;
  setup.simplifySolution();
  og::PathGeometric path = setup.getSolutionPath();
  if (!curved) {
    std::vector<Eigen::Vector2d> corners;
    for (std::size_t i = 0; i < path.getStateCount(); ++i) corners.push_back(PositionOf(path.getState(i), false));
    return corners;
  }
  return PointsAlong(path);
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
                     const PlannerOptions& options, double start_yaw) {
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

  // Straight segments, keeping the margin where there is room. With a turning radius, curves
  // instead, at the largest margin that has them, unless they detour more than a full turn beyond
  // the straight path (RRT*'s curves through a narrow gap can), or none is found (a start facing a
  // wall closer than the radius): then the straight segments, which the robot walks as best it turns.
  std::vector<double> margins{options.clearance_margin};
  if (options.clearance_margin > 0.0) margins.push_back(0.0);
  std::optional<std::vector<Eigen::Vector2d>> points;
  double margin = 0.0;
  for (size_t m = 0; m < margins.size() && !points; ++m) {
    points = Solve(map, from, start_yaw, goal, options, margins[m], 0.0);
    margin = margins[m];
  }
  if (!points) {
    result.status = PlannedPath::Status::kNoPath;
    result.message = "no collision-free path from " + Where(start) + " to " + Where(goal) + " found in " +
                     std::to_string(options.time_limit) + " s";
  } else {
    const double detour = PolylineLength(*points) + 2.0 * M_PI * options.turning_radius;
    for (size_t m = 0; m < margins.size() && options.turning_radius > 0.0; ++m) {
      std::optional<std::vector<Eigen::Vector2d>> curve =
          Solve(map, from, start_yaw, goal, options, margins[m], options.turning_radius, *points);
      if (curve && PolylineLength(*curve) <= detour) {
        points = std::move(curve);
        margin = margins[m];
        result.turning_radius = options.turning_radius;
        break;
      }
    }
    if (from != start) points->insert(points->begin(), start);
    result.status = PlannedPath::Status::kFound;
    result.margin = margin;
    result.length = PolylineLength(*points);
    result.waypoints = Densify(*points, options.waypoint_spacing);
  }
  result.planning_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return result;
}

}  // namespace flsd
