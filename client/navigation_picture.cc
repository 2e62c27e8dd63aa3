#include "client/navigation_picture.h"

#include <cmath>

#include "report/svg_plot.h"

namespace flsd {

void WriteNavigationPicture(const std::string& path, const std::optional<Map2D>& map, const NavigationRecord& r) {
  std::vector<double> xs = r.walked_x, ys = r.walked_y;
  xs.push_back(r.goal_x);
  ys.push_back(r.goal_y);
  for (const std::vector<double>& p : r.planned) {
    for (size_t i = 0; i + 1 < p.size(); i += 2) {
      xs.push_back(p[i]);
      ys.push_back(p[i + 1]);
    }
  }
  SvgPlot::Range x = SvgPlot::Covering(xs, 0.1), y = SvgPlot::Covering(ys, 0.1);
  if (map) x = {map->x_min, map->x_max}, y = {map->y_min, map->y_max};
  SvgPlot plot(900, 700, x, y, /*equal_aspect=*/true);
  plot.Title(r.outcome);
  plot.Labels("x (m)", "y (m)");
  if (map) {
    for (const Map2D::Circle& c : map->circles) {
      plot.Circle(c.center.x(), c.center.y(), c.radius + map->robot_radius, "#f2d9d9");
      plot.Circle(c.center.x(), c.center.y(), c.radius, "#999999");
    }
    for (const Map2D::Polygon& polygon : map->polygons) {
      std::vector<double> px, py;
      for (const Eigen::Vector2d& v : polygon) px.push_back(v.x()), py.push_back(v.y());
      plot.Polygon(px, py, "#999999");
    }
  }
  for (size_t k = 0; k < r.planned.size(); ++k) {
    std::vector<double> px, py;
    for (size_t i = 0; i + 1 < r.planned[k].size(); i += 2) px.push_back(r.planned[k][i]), py.push_back(r.planned[k][i + 1]);
    const bool first = k == 0;
    plot.Line(px, py, first ? "#1f77b4" : "#9ecae1", first ? "planned path" : (k == 1 ? "replanned" : ""), 2.0, true);
  }
  plot.Line(r.walked_x, r.walked_y, "#d62728", "walked", 2.5);
  if (!r.walked_x.empty()) plot.Marker(r.walked_x.front(), r.walked_y.front(), "#2ca02c", "start");
  plot.Marker(r.goal_x, r.goal_y, "#ffbf00", "goal");
  plot.Save(path);
}

}  // namespace flsd
