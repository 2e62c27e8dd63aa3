#include "report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/atomic_file.h"

namespace flsd {
namespace {

constexpr int kLeft = 70, kRight = 150, kTop = 40, kBottom = 50;  // margins, px

std::string Number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      default: out += c;
    }
  }
  return out;
}

// About five round tick values across [lo, hi].
std::vector<double> Ticks(double lo, double hi) {
  const double span = hi - lo;
  if (!(span > 0.0)) return {lo};
  const double raw = span / 5.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * magnitude >= raw) {
      step = m * magnitude;
      break;
    }
  }
  std::vector<double> ticks;
  for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * span; t += step) ticks.push_back(std::abs(t) < 1e-12 * span ? 0.0 : t);
  return ticks;
}

}  // namespace

SvgPlot::SvgPlot(int width, int height, Range x, Range y, bool equal_aspect)
    : width_(width), height_(height), x_(x), y_(y) {
  if (!(x_.hi > x_.lo)) x_.hi = x_.lo + 1.0;
  if (!(y_.hi > y_.lo)) y_.hi = y_.lo + 1.0;
  if (equal_aspect) {
    const double plot_w = width_ - kLeft - kRight, plot_h = height_ - kTop - kBottom;
    const double scale = std::max((x_.hi - x_.lo) / plot_w, (y_.hi - y_.lo) / plot_h);  // m per px
    const double cx = 0.5 * (x_.lo + x_.hi), cy = 0.5 * (y_.lo + y_.hi);
    x_ = {cx - 0.5 * scale * plot_w, cx + 0.5 * scale * plot_w};
    y_ = {cy - 0.5 * scale * plot_h, cy + 0.5 * scale * plot_h};
  }
}

SvgPlot::Range SvgPlot::Covering(const std::vector<double>& values, double margin) {
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (!std::isfinite(lo)) return {0.0, 1.0};
  const double pad = (hi > lo ? hi - lo : 1.0) * margin;
  return {lo - pad, hi + pad};
}

double SvgPlot::X(double x) const { return kLeft + (x - x_.lo) / (x_.hi - x_.lo) * (width_ - kLeft - kRight); }
double SvgPlot::Y(double y) const { return height_ - kBottom - (y - y_.lo) / (y_.hi - y_.lo) * (height_ - kTop - kBottom); }

void SvgPlot::Line(const std::vector<double>& xs, const std::vector<double>& ys, const std::string& color,
                   const std::string& name, double width, bool dashed) {
  std::ostringstream path;
  bool pen_down = false;
  for (size_t i = 0; i < std::min(xs.size(), ys.size()); ++i) {
    if (!std::isfinite(xs[i]) || !std::isfinite(ys[i])) {
      pen_down = false;
      continue;
    }
    path << (pen_down ? " L" : " M") << Number(X(xs[i])) << ' ' << Number(Y(ys[i]));
    pen_down = true;
  }
  body_ += "<path d=\"" + path.str() + "\" fill=\"none\" stroke=\"" + color + "\" stroke-width=\"" + Number(width) +
           "\"" + (dashed ? " stroke-dasharray=\"6 4\"" : "") + " stroke-linejoin=\"round\"/>\n";
  if (!name.empty()) legend_.emplace_back(name, color);
}

void SvgPlot::Circle(double x, double y, double radius, const std::string& fill, const std::string& name) {
  const double r = radius / (x_.hi - x_.lo) * (width_ - kLeft - kRight);
  body_ += "<circle cx=\"" + Number(X(x)) + "\" cy=\"" + Number(Y(y)) + "\" r=\"" + Number(r) + "\" fill=\"" + fill +
           "\"/>\n";
  if (!name.empty()) legend_.emplace_back(name, fill);
}

void SvgPlot::Polygon(const std::vector<double>& xs, const std::vector<double>& ys, const std::string& fill) {
  std::string points;
  for (size_t i = 0; i < std::min(xs.size(), ys.size()); ++i) points += Number(X(xs[i])) + "," + Number(Y(ys[i])) + " ";
  body_ += "<polygon points=\"" + points + "\" fill=\"" + fill + "\"/>\n";
}

void SvgPlot::Dot(double x, double y, double pixels, const std::string& fill) {
  body_ += "<circle cx=\"" + Number(X(x)) + "\" cy=\"" + Number(Y(y)) + "\" r=\"" + Number(pixels) + "\" fill=\"" + fill +
           "\"/>\n";
}

void SvgPlot::Marker(double x, double y, const std::string& color, const std::string& name) {
  body_ += "<circle cx=\"" + Number(X(x)) + "\" cy=\"" + Number(Y(y)) + "\" r=\"6\" fill=\"" + color +
           "\" stroke=\"black\"/>\n";
  if (!name.empty()) legend_.emplace_back(name, color);
}

std::string SvgPlot::Render() const {
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width_ << "\" height=\"" << height_
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  const double x0 = X(x_.lo), x1 = X(x_.hi), y0 = Y(y_.lo), y1 = Y(y_.hi);
  for (double t : Ticks(x_.lo, x_.hi)) {
    svg << "<line x1=\"" << Number(X(t)) << "\" y1=\"" << Number(y0) << "\" x2=\"" << Number(X(t)) << "\" y2=\""
        << Number(y1) << "\" stroke=\"#e4e4e4\"/>\n<text x=\"" << Number(X(t)) << "\" y=\"" << Number(y0 + 16)
        << "\" text-anchor=\"middle\">" << Number(t) << "</text>\n";
  }
  for (double t : Ticks(y_.lo, y_.hi)) {
    svg << "<line x1=\"" << Number(x0) << "\" y1=\"" << Number(Y(t)) << "\" x2=\"" << Number(x1) << "\" y2=\""
        << Number(Y(t)) << "\" stroke=\"#e4e4e4\"/>\n<text x=\"" << Number(x0 - 6) << "\" y=\"" << Number(Y(t) + 4)
        << "\" text-anchor=\"end\">" << Number(t) << "</text>\n";
  }
  svg << "<rect x=\"" << Number(x0) << "\" y=\"" << Number(y1) << "\" width=\"" << Number(x1 - x0) << "\" height=\""
      << Number(y0 - y1) << "\" fill=\"none\" stroke=\"black\"/>\n";
  svg << "<svg x=\"" << Number(x0) << "\" y=\"" << Number(y1) << "\" width=\"" << Number(x1 - x0) << "\" height=\""
      << Number(y0 - y1) << "\" viewBox=\"" << Number(x0) << ' ' << Number(y1) << ' ' << Number(x1 - x0) << ' '
      << Number(y0 - y1) << "\" overflow=\"hidden\">\n"
      << body_ << "</svg>\n";
  svg << "<text x=\"" << Number(0.5 * (x0 + x1)) << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">"
      << Escape(title_) << "</text>\n";
  svg << "<text x=\"" << Number(0.5 * (x0 + x1)) << "\" y=\"" << height_ - 12 << "\" text-anchor=\"middle\">"
      << Escape(x_label_) << "</text>\n";
  svg << "<text transform=\"translate(16," << Number(0.5 * (y0 + y1)) << ") rotate(-90)\" text-anchor=\"middle\">"
      << Escape(y_label_) << "</text>\n";
  for (size_t i = 0; i < legend_.size(); ++i) {
    const double y = y1 + 10 + 20 * i;
    svg << "<rect x=\"" << Number(x1 + 12) << "\" y=\"" << Number(y) << "\" width=\"14\" height=\"10\" fill=\""
        << legend_[i].second << "\"/>\n<text x=\"" << Number(x1 + 32) << "\" y=\"" << Number(y + 10) << "\">"
        << Escape(legend_[i].first) << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

void SvgPlot::Save(const std::string& path) const { WriteFileAtomically(path, Render()); }

}  // namespace flsd
