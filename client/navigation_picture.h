#pragma once
// The picture of a navigation: the map's obstacles (inflated outline dashed), every path the
// server planned (the first and each replan), and the path the robot actually walked.

#include <optional>
#include <string>
#include <vector>

#include "navigation_map/map2d.h"

namespace flsd {

struct NavigationRecord {
  std::vector<std::vector<double>> planned;  // each x0 y0 x1 y1 ..., in the order they came
  std::vector<double> walked_x, walked_y;
  double goal_x = 0.0, goal_y = 0.0;
  std::string outcome;  // "navigate succeeded: reached ..."
};

// Writes an SVG to `path` (atomically).
void WriteNavigationPicture(const std::string& path, const std::optional<Map2D>& map, const NavigationRecord& record);

}  // namespace flsd
