#pragma once
// A 2-D map for navigation: rectangular bounds, circular and polygonal obstacles, all inflated by
// the robot's radius, so that the robot is a point to the planner. Read from YAML:
//
//   bounds: [x_min, x_max, y_min, y_max]      # m
//   robot_radius: 0.35                        # m, inflation of every obstacle and of the bounds
//   circles: [{center: [x, y], radius: r}, ...]
//   polygons: [[[x, y], [x, y], [x, y], ...], ...]   # simple polygons, any winding

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace flsd {

struct Map2D {
  struct Circle {
    Eigen::Vector2d center = Eigen::Vector2d::Zero();
    double radius = 0.0;
  };
  using Polygon = std::vector<Eigen::Vector2d>;

  double x_min = -5.0, x_max = 5.0, y_min = -5.0, y_max = 5.0;
  double robot_radius = 0.35;  // m: the A1 is 0.5 m long, 0.3 m wide, and its stride reaches
  std::vector<Circle> circles;
  std::vector<Polygon> polygons;

  // What a map may hold, so that reading one and every collision check against it stay cheap
  // whatever a client sends: YAML aliases count as often as they are used (a few bytes of `*p`
  // can stand for thousands of points), and bounds stay finite and near (OMPL samples in them).
  static constexpr std::size_t kMaxTextBytes = 64 * 1024;
  static constexpr std::size_t kMaxShapePoints = 4096;  // polygon vertices plus circles
  static constexpr double kMaxExtent = 1000.0;          // m, |any bound| and any radius

  // Parses YAML `text`; `source` names it in messages ("configs/maps/wall.yaml", "request").
  // Throws InputError naming the key and what was expected.
  static Map2D Parse(const std::string& text, const std::string& source);
  static Map2D Load(const std::string& path);
  // The YAML that Parse reads back to this map (to the last of 17 significant digits).
  std::string ToYaml() const;
  // The same map in a frame whose origin is at `origin` of this one: a map to send with a
  // navigate request for a robot at `origin` that the server believes at (0, 0).
  Map2D Shifted(const Eigen::Vector2d& origin) const;

  // Distance from p to the nearest obstacle or bound edge, before inflation; negative inside.
  double Clearance(const Eigen::Vector2d& p) const;
  // Whether a robot centred at p touches nothing (clearance at least the robot's radius).
  bool IsFree(const Eigen::Vector2d& p) const { return Clearance(p) >= robot_radius; }
};

}  // namespace flsd
