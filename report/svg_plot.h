#pragma once
// A small SVG chart: data-space axes with ticks and labels, polylines, circles, polygons and a
// legend. Enough for learning curves and navigation maps, readable in any browser, no plotting
// library needed. Plain C++.

#include <string>
#include <vector>

namespace flsd {

class SvgPlot {
 public:
  struct Range {
    double lo = 0.0, hi = 1.0;
  };

  // A plot area of width x height pixels showing x and y ranges. `equal_aspect` widens one range
  // so that a metre is as long across as up (maps).
  SvgPlot(int width, int height, Range x, Range y, bool equal_aspect = false);

  void Title(const std::string& text) { title_ = text; }
  void Labels(const std::string& x, const std::string& y) {
    x_label_ = x;
    y_label_ = y;
  }
  // A polyline through (xs[i], ys[i]); non-finite points break it. Named lines go in the legend.
  void Line(const std::vector<double>& xs, const std::vector<double>& ys, const std::string& color,
            const std::string& name = "", double width = 2.0, bool dashed = false);
  void Circle(double x, double y, double radius, const std::string& fill, const std::string& name = "");
  void Polygon(const std::vector<double>& xs, const std::vector<double>& ys, const std::string& fill);
  // A legend entry without a mark in the plot (scatter plots, bands).
  void Legend(const std::string& name, const std::string& color) { legend_.emplace_back(name, color); }
  // A dot of `pixels` radius (scatter plots).
  void Dot(double x, double y, double pixels, const std::string& fill);
  // A marker of fixed pixel size (start, goal).
  void Marker(double x, double y, const std::string& color, const std::string& name);

  std::string Render() const;
  // Writes atomically; throws InputError naming the path on failure.
  void Save(const std::string& path) const;

  // A range covering `values` (finite ones) with a margin, or [0, 1] if there are none.
  static Range Covering(const std::vector<double>& values, double margin = 0.05);

 private:
  double X(double x) const;
  double Y(double y) const;

  int width_, height_;
  Range x_, y_;
  std::string title_, x_label_, y_label_;
  std::string body_;
  std::vector<std::pair<std::string, std::string>> legend_;  // name, color
};

}  // namespace flsd
