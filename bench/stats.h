#pragma once
// Summary statistics for benchmarks.

#include <algorithm>
#include <cmath>
#include <vector>

namespace flsd {

// The q-quantile (0..1) of `values` by the nearest-rank method; 0 for no values.
inline double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const size_t rank = static_cast<size_t>(std::ceil(q * values.size()));
  const size_t index = rank == 0 ? 0 : std::min(values.size() - 1, rank - 1);
  std::nth_element(values.begin(), values.begin() + index, values.end());
  return values[index];
}

// The arithmetic mean; 0 for no values.
inline double Mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return values.empty() ? 0.0 : sum / values.size();
}

// The least-squares slope of y over x; 0 for fewer than two distinct x.
inline double Slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double mx = Mean(x), my = Mean(y);
  double sxy = 0.0, sxx = 0.0;
  for (size_t i = 0; i < x.size() && i < y.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
  }
  return sxx > 0.0 ? sxy / sxx : 0.0;
}

}  // namespace flsd
