#include "report/learning_curves.h"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <utility>

#include "core/check.h"
#include "report/svg_plot.h"

namespace flsd {
namespace {

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
  return cells;
}

}  // namespace

std::vector<double> ReadCsvColumn(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read");
  std::string line;
  if (!std::getline(in, line)) throw InputError(path + ": empty (expected a header row)");
  const std::vector<std::string> header = SplitCsv(line);
  size_t column = header.size();
  for (size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) column = i;
  }
  if (column == header.size()) throw InputError(path + ": no column '" + name + "'; the columns are " + line);
  std::vector<double> values;
  for (int row = 2; std::getline(in, line); ++row) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = SplitCsv(line);
    try {
      if (column >= cells.size()) throw std::invalid_argument("missing");
      values.push_back(std::stod(cells[column]));
    } catch (const std::exception&) {
      throw InputError(path + ":" + std::to_string(row) + ": column '" + name + "' is not a number");
    }
  }
  return values;
}

std::vector<double> MovingAverage(const std::vector<double>& values, int window) {
  std::vector<double> out(values.size());
  double sum = 0.0;
  for (size_t i = 0; i < values.size(); ++i) {
    sum += values[i];
    if (static_cast<int>(i) >= window) sum -= values[i - window];
    out[i] = sum / std::min<double>(window, i + 1);
  }
  return out;
}

SeedSpread SpreadOverSeeds(const std::vector<std::vector<double>>& seeds) {
  SeedSpread s;
  if (seeds.empty()) return s;
  size_t rows = seeds.front().size();
  for (const std::vector<double>& seed : seeds) rows = std::min(rows, seed.size());
  for (size_t i = 0; i < rows; ++i) {
    double sum = 0.0, low = seeds.front()[i], high = low;
    for (const std::vector<double>& seed : seeds) {
      sum += seed[i];
      low = std::min(low, seed[i]);
      high = std::max(high, seed[i]);
    }
    s.mean.push_back(sum / static_cast<double>(seeds.size()));
    s.low.push_back(low);
    s.high.push_back(high);
  }
  return s;
}

void PlotCurves(const std::vector<CurveSpec>& curves, const CurvePlotOptions& options) {
  static const char* const kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
  std::vector<std::vector<double>> xs;
  std::vector<SeedSpread> ys;
  std::vector<double> all_x, all_y;
  for (const CurveSpec& c : curves) {
    if (c.csvs.empty()) throw InputError("plot: the curve '" + c.label + "' has no progress.csv");
    std::vector<std::vector<double>> seeds;
    for (const std::string& csv : c.csvs) {
      seeds.push_back(MovingAverage(ReadCsvColumn(csv, options.y), std::max(1, options.smooth)));
    }
    SeedSpread y = SpreadOverSeeds(seeds);
    std::vector<double> x = ReadCsvColumn(c.csvs.front(), options.x);
    // Seeds are averaged row by row: their x columns must agree where they overlap.
    for (size_t seed = 1; seed < c.csvs.size(); ++seed) {
      const std::string& csv = c.csvs[seed];
      const std::vector<double> other = ReadCsvColumn(csv, options.x);
      for (size_t i = 0; i < std::min({x.size(), other.size(), y.mean.size()}); ++i) {
        if (other[i] != x[i]) {
          throw InputError(csv + ": row " + std::to_string(i + 2) + " has " + options.x + " " + std::to_string(other[i]) +
                           ", but " + c.csvs.front() + " has " + std::to_string(x[i]) + ": seeds of '" + c.label +
                           "' must share their " + options.x + " column");
        }
      }
    }
    const size_t rows = std::min(x.size(), y.mean.size());
    for (std::vector<double>* v : {&x, &y.mean, &y.low, &y.high}) v->resize(rows);
    xs.push_back(std::move(x));
    ys.push_back(std::move(y));
    all_x.insert(all_x.end(), xs.back().begin(), xs.back().end());
    all_y.insert(all_y.end(), ys.back().low.begin(), ys.back().low.end());
    all_y.insert(all_y.end(), ys.back().high.begin(), ys.back().high.end());
  }
  SvgPlot plot(900, 500, SvgPlot::Covering(all_x, 0.0), SvgPlot::Covering(all_y));
  plot.Title(options.title);
  plot.Labels(options.x, options.y + (options.smooth > 1 ? " (mean of " + std::to_string(options.smooth) + " iterations)" : ""));
  for (size_t i = 0; i < curves.size(); ++i) {
    const std::string color = kColors[i % 6];
    if (curves[i].csvs.size() > 1) {  // the band: along the highest, back along the lowest
      std::vector<double> band_x = xs[i], band_y = ys[i].high;
      band_x.insert(band_x.end(), xs[i].rbegin(), xs[i].rend());
      band_y.insert(band_y.end(), ys[i].low.rbegin(), ys[i].low.rend());
      plot.Polygon(band_x, band_y, color + "33");  // 20 % opaque
    }
    const std::string label = curves[i].label + (curves[i].csvs.size() > 1
                                                     ? " (mean of " + std::to_string(curves[i].csvs.size()) + " seeds)"
                                                     : "");
    plot.Line(xs[i], ys[i].mean, color, label);
  }
  plot.Save(options.output);
}

}  // namespace flsd
