#include "navigation_map/map2d.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/check.h"
#include "core/paths.h"

namespace flsd {
namespace {

Eigen::Vector2d Point(const YAML::Node& node, const std::string& where) {
  if (!node.IsSequence() || node.size() != 2) throw InputError(where + ": expected a point [x, y]");
  const Eigen::Vector2d p(node[0].as<double>(), node[1].as<double>());
  if (!p.allFinite()) throw InputError(where + ": expected finite coordinates");
  return p;
}

double SegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = ab.squaredNorm() > 0.0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

bool Inside(const Eigen::Vector2d& p, const Map2D::Polygon& polygon) {
  bool inside = false;
  for (size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

// A length in [-kMaxExtent, kMaxExtent].
double Length(const YAML::Node& node, const std::string& where) {
  const double v = node.as<double>();
  if (!(std::abs(v) <= Map2D::kMaxExtent)) {
    char text[128];
    std::snprintf(text, sizeof text, ": expected a finite number within [%g, %g] m, got %g", -Map2D::kMaxExtent,
                  Map2D::kMaxExtent, v);
    throw InputError(where + text);
  }
  return v;
}

}  // namespace

Map2D Map2D::Parse(const std::string& text, const std::string& source) {
  if (text.size() > kMaxTextBytes) {
    throw InputError(source + ": " + std::to_string(text.size()) + " bytes; a map may have at most " +
                     std::to_string(kMaxTextBytes));
  }
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(source + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
  }
  if (!root.IsMap()) throw InputError(source + ": expected a map with bounds, robot_radius, circles, polygons");
  Map2D map;
  std::size_t points = 0;  // as read, aliases counted each time they are used
  const auto count = [&](std::size_t n, const std::string& where) {
    points += n;
    if (points > kMaxShapePoints) {
      throw InputError(where + ": more than " + std::to_string(kMaxShapePoints) +
                       " polygon points and circles in the map (YAML aliases count each time they are used)");
    }
  };
  try {
    for (const auto& entry : root) {
      const std::string key = entry.first.as<std::string>();
      const YAML::Node& value = entry.second;
      const std::string where = source + ": " + key;
      if (key == "bounds") {
        if (!value.IsSequence() || value.size() != 4) throw InputError(where + ": expected [x_min, x_max, y_min, y_max]");
        static const char* const kNames[] = {"x_min", "x_max", "y_min", "y_max"};
        double b[4];
        for (int i = 0; i < 4; ++i) b[i] = Length(value[i], where + "[" + std::to_string(i) + "] (" + kNames[i] + ")");
        map.x_min = b[0];
        map.x_max = b[1];
        map.y_min = b[2];
        map.y_max = b[3];
        if (!(map.x_min < map.x_max && map.y_min < map.y_max)) throw InputError(where + ": expected min < max");
      } else if (key == "robot_radius") {
        map.robot_radius = value.as<double>();
        if (!(map.robot_radius >= 0.0 && map.robot_radius < 5.0)) throw InputError(where + ": expected [0, 5) m");
      } else if (key == "circles") {
        for (size_t i = 0; i < value.size(); ++i) {
          const std::string at = where + "[" + std::to_string(i) + "]";
          count(1, at);
          Circle c{Point(value[i]["center"], at + ".center"), Length(value[i]["radius"], at + ".radius")};
          if (!(c.radius > 0.0)) throw InputError(at + ".radius: expected a positive radius");
          map.circles.push_back(c);
        }
      } else if (key == "polygons") {
        for (size_t i = 0; i < value.size(); ++i) {
          const std::string at = where + "[" + std::to_string(i) + "]";
          if (!value[i].IsSequence() || value[i].size() < 3) throw InputError(at + ": expected at least 3 points");
          count(value[i].size(), at);
          Polygon polygon;
          for (size_t k = 0; k < value[i].size(); ++k) polygon.push_back(Point(value[i][k], at + "[" + std::to_string(k) + "]"));
          map.polygons.push_back(std::move(polygon));
        }
      } else {
        throw InputError(where + ": unknown key (expected bounds, robot_radius, circles, polygons)");
      }
    }
  } catch (const YAML::Exception& e) {
    throw InputError(source + ": " + e.what());
  }
  return map;
}

Map2D Map2D::Load(const std::string& path) {
  const std::string file = ResolveDataPath(path);
  std::ifstream in(file);
  if (!in) throw InputError(file + ": cannot open map");
  std::stringstream text;
  text << in.rdbuf();
  return Parse(text.str(), file);
}

std::string Map2D::ToYaml() const {
  std::ostringstream out;
  out.precision(17);
  const auto point = [&](const Eigen::Vector2d& p) { out << '[' << p.x() << ", " << p.y() << ']'; };
  out << "bounds: [" << x_min << ", " << x_max << ", " << y_min << ", " << y_max << "]\n";
  out << "robot_radius: " << robot_radius << "\n";
  out << "circles:\n";
  for (const Circle& c : circles) {
    out << "  - {center: ";
    point(c.center);
    out << ", radius: " << c.radius << "}\n";
  }
  out << "polygons:\n";
  for (const Polygon& polygon : polygons) {
    out << "  - [";
    for (size_t i = 0; i < polygon.size(); ++i) {
      if (i > 0) out << ", ";
      point(polygon[i]);
    }
    out << "]\n";
  }
  return out.str();
}

Map2D Map2D::Shifted(const Eigen::Vector2d& origin) const {
  Map2D out = *this;
  out.x_min -= origin.x();
  out.x_max -= origin.x();
  out.y_min -= origin.y();
  out.y_max -= origin.y();
  for (Circle& c : out.circles) c.center -= origin;
  for (Polygon& polygon : out.polygons) {
    for (Eigen::Vector2d& p : polygon) p -= origin;
  }
  return out;
}

double Map2D::Clearance(const Eigen::Vector2d& p) const {
  double clearance = std::min({p.x() - x_min, x_max - p.x(), p.y() - y_min, y_max - p.y()});
  for (const Circle& c : circles) clearance = std::min(clearance, (p - c.center).norm() - c.radius);
  for (const Polygon& polygon : polygons) {
    double edge = HUGE_VAL;
    for (size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
      edge = std::min(edge, SegmentDistance(p, polygon[j], polygon[i]));
    }
    clearance = std::min(clearance, Inside(p, polygon) ? -edge : edge);
  }
  return clearance;
}

}  // namespace flsd
