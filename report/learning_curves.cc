#include "report/learning_curves.h"

#include <fstream>
#include <sstream>

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

void PlotCurves(const std::vector<CurveSpec>& curves, const CurvePlotOptions& options) {
  static const char* const kColors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
  std::vector<std::vector<double>> xs, ys;
  std::vector<double> all_x, all_y;
  for (const CurveSpec& c : curves) {
    xs.push_back(ReadCsvColumn(c.csv, options.x));
    ys.push_back(MovingAverage(ReadCsvColumn(c.csv, options.y), std::max(1, options.smooth)));
    all_x.insert(all_x.end(), xs.back().begin(), xs.back().end());
    all_y.insert(all_y.end(), ys.back().begin(), ys.back().end());
  }
  SvgPlot plot(900, 500, SvgPlot::Covering(all_x, 0.0), SvgPlot::Covering(all_y));
  plot.Title(options.title);
  plot.Labels(options.x, options.y + (options.smooth > 1 ? " (mean of " + std::to_string(options.smooth) + " iterations)" : ""));
  for (size_t i = 0; i < curves.size(); ++i) plot.Line(xs[i], ys[i], kColors[i % 6], curves[i].label);
  plot.Save(options.output);
}

}  // namespace flsd
