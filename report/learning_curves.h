#pragma once
// Learning curves from runs' progress.csv files, drawn on one chart (the paper's Fig. 8 for the
// velocity task; any column of any run). Plain C++.

#include <string>
#include <vector>

namespace flsd {

struct CurveSpec {
  std::string label;
  // progress.csv files, one per seed: their mean is drawn, with the band between the lowest and
  // the highest seed where there are several.
  std::vector<std::string> csvs;
};

// Per row, over the seeds' series (truncated to the shortest): the mean, the lowest and the
// highest.
struct SeedSpread {
  std::vector<double> mean, low, high;
};
SeedSpread SpreadOverSeeds(const std::vector<std::vector<double>>& seeds);

struct CurvePlotOptions {
  std::string x = "env_steps";
  std::string y = "mean_reward";
  int smooth = 1;  // moving average over this many rows
  std::string title;
  std::string output;  // .svg
};

// The column `name` of a CSV file with a header row. Throws InputError naming the file and the
// column (and listing the columns there are) if it is missing or a value is not a number.
std::vector<double> ReadCsvColumn(const std::string& path, const std::string& name);

// The trailing moving average of `values` over `window` entries (fewer at the start).
std::vector<double> MovingAverage(const std::vector<double>& values, int window);

// Draws every curve and writes options.output.
void PlotCurves(const std::vector<CurveSpec>& curves, const CurvePlotOptions& options);

}  // namespace flsd
