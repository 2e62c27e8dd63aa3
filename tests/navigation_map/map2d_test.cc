// Map2D: clearances with known answers, inflation by the robot's radius, and errors that name
// the key for bad maps.

#include "navigation_map/map2d.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;
using testutil::InputErrorMessage;

TEST(Map2D, ClearanceIsTheDistanceToTheNearestObstacleOrEdge) {
  const Map2D map = Map2D::Parse(
      "bounds: [-5, 5, -5, 5]\nrobot_radius: 0.3\ncircles: [{center: [2, 0], radius: 1}]\n"
      "polygons: [[[-3, -1], [-2, -1], [-2, 1], [-3, 1]]]\n",
      "test");
  EXPECT_DOUBLE_EQ(map.Clearance(Eigen::Vector2d(0.0, 0.0)), 1.0);   // circle edge at x = 1
  EXPECT_DOUBLE_EQ(map.Clearance(Eigen::Vector2d(0.0, 4.5)), 0.5);   // the top bound
  EXPECT_DOUBLE_EQ(map.Clearance(Eigen::Vector2d(2.0, 0.5)), -0.5);  // inside the circle
  EXPECT_DOUBLE_EQ(map.Clearance(Eigen::Vector2d(-2.5, 0.0)), -0.5);  // inside the box
  EXPECT_NEAR(map.Clearance(Eigen::Vector2d(-1.0, 2.0)), std::hypot(1.0, 1.0), 1e-12);  // box corner
  EXPECT_TRUE(map.IsFree(Eigen::Vector2d(0.0, 0.0)));
  EXPECT_FALSE(map.IsFree(Eigen::Vector2d(0.75, 0.0)));  // 0.25 m from the circle < 0.3
}

TEST(Map2D, ShippedMapsLoad) {
  for (const char* name : {"open", "wall_gap", "enclosed", "demo"}) {
    const Map2D map = Map2D::Load(std::string("configs/maps/") + name + ".yaml");
    EXPECT_GT(map.x_max, map.x_min) << name;
  }
}

// ToYaml writes what Parse reads back exactly, and a shifted map has every clearance of the
// original at the shifted point: what a client sends for a robot the server believes at (0, 0).
TEST(Map2D, RoundTripsThroughYamlAndShiftsItsOrigin) {
  for (const char* name : {"open", "wall_gap", "enclosed", "demo"}) {
    const Map2D map = Map2D::Load(std::string("configs/maps/") + name + ".yaml");
    const Map2D back = Map2D::Parse(map.ToYaml(), name);
    EXPECT_EQ(back.ToYaml(), map.ToYaml()) << name;
    EXPECT_EQ(back.circles.size(), map.circles.size());
    EXPECT_EQ(back.polygons.size(), map.polygons.size());
    const Eigen::Vector2d origin(1.0 / 3.0, -2.7);
    const Map2D shifted = Map2D::Parse(map.Shifted(origin).ToYaml(), name);
    EXPECT_DOUBLE_EQ(shifted.x_min, map.x_min - origin.x());
    for (const Eigen::Vector2d p : {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(1.5, 0.2), Eigen::Vector2d(-4.1, 3.3)}) {
      EXPECT_NEAR(shifted.Clearance(p - origin), map.Clearance(p), 1e-12) << name << " at " << p.transpose();
    }
  }
}

// A map is bounded whatever a client sends: its size, its points (YAML aliases counted each time
// they are used: a few bytes of `*p` can stand for thousands of points) and its extent.
TEST(Map2D, MapsAreBoundedInSizePointsAndExtent) {
  std::string polygon = "[";
  for (int i = 0; i < 2000; ++i) {
    const double a = 2.0 * M_PI * i / 2000;
    char point[48];
    std::snprintf(point, sizeof point, "%s[%.2f, %.2f]", i ? ", " : "", 50 + std::cos(a), 50 + std::sin(a));
    polygon += point;
  }
  polygon += "]";
  std::string bomb = "bounds: [-100, 100, -100, 100]\npolygons:\n  - &p " + polygon + "\n";
  for (int i = 0; i < 2499; ++i) bomb += "  - *p\n";
  const auto start = std::chrono::steady_clock::now();
  EXPECT_THAT(InputErrorMessage([&] { Map2D::Parse(bomb, "m.yaml"); }),
              HasSubstr("m.yaml: polygons[2]: more than 4096 polygon points and circles in the map (YAML aliases count"));
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.5);
  // Two uses of the polygon are within the bound.
  const std::string two = "bounds: [-100, 100, -100, 100]\npolygons:\n  - &p " + polygon + "\n  - *p\n";
  EXPECT_EQ(Map2D::Parse(two, "m.yaml").polygons.size(), 2u);

  EXPECT_THAT(InputErrorMessage([] { Map2D::Parse(std::string(Map2D::kMaxTextBytes + 1, '#'), "m.yaml"); }),
              HasSubstr("m.yaml: 65537 bytes; a map may have at most 65536"));
  EXPECT_THAT(InputErrorMessage([] { Map2D::Parse("bounds: [-5, .inf, -5, 5]", "m.yaml"); }),
              HasSubstr("m.yaml: bounds[1] (x_max): expected a finite number within [-1000, 1000] m, got inf"));
  EXPECT_THAT(InputErrorMessage([] { Map2D::Parse("bounds: [-5, 5, -1e300, 5]", "m.yaml"); }),
              HasSubstr("bounds[2] (y_min): expected a finite number within [-1000, 1000] m, got -1e+300"));
  EXPECT_THAT(InputErrorMessage([] { Map2D::Parse("circles: [{center: [0, 0], radius: .inf}]", "m.yaml"); }),
              HasSubstr("circles[0].radius: expected a finite number"));
  EXPECT_THAT(InputErrorMessage([] { Map2D::Parse(std::string(5000, '[') + std::string(5000, ']'), "m.yaml"); }),
              HasSubstr("m.yaml"));
}

TEST(Map2D, BadMapsAreErrorsThatNameTheKey) {
  EXPECT_THAT(InputErrorMessage([] { Map2D::Parse("bounds: [1, 0, 0, 1]", "m.yaml"); }),
              HasSubstr("m.yaml: bounds: expected min < max"));
  EXPECT_THAT(InputErrorMessage([] { Map2D::Parse("circles: [{center: [0, 0], radius: -1}]", "m.yaml"); }),
              HasSubstr("m.yaml: circles[0].radius: expected a positive radius"));
  EXPECT_THAT(InputErrorMessage([] { Map2D::Parse("polygons: [[[0, 0], [1, 1]]]", "m.yaml"); }),
              HasSubstr("polygons[0]: expected at least 3 points"));
  EXPECT_THAT(InputErrorMessage([] { Map2D::Parse("walls: []", "m.yaml"); }), HasSubstr("m.yaml: walls: unknown key"));
  EXPECT_THAT(InputErrorMessage([] { Map2D::Parse("bounds: [0, 1", "m.yaml"); }), HasSubstr("malformed YAML"));
  EXPECT_THAT(InputErrorMessage([] { Map2D::Load("/nonexistent/map.yaml"); }), HasSubstr("/nonexistent/map.yaml"));
}

}  // namespace
}  // namespace flsd
