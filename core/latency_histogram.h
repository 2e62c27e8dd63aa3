#pragma once
// Counts durations (tick lateness, round trips) in 10 us bins up to 50 ms, the last bin holding
// everything longer: quantiles to 10 us, no allocation when adding, safe to read while another
// thread adds (each bin is atomic; a read sees some recent snapshot).

#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>

namespace flsd {

class LatencyHistogram {
 public:
  static constexpr double kBinSeconds = 10e-6;
  static constexpr int kBins = 5001;

  void Add(double seconds) {
    const double bin = seconds > 0.0 ? seconds / kBinSeconds : 0.0;
    const int index = bin >= kBins - 1 ? kBins - 1 : static_cast<int>(bin);
    bins_[index].fetch_add(1, std::memory_order_relaxed);
    count_.fetch_add(1, std::memory_order_relaxed);
  }

  uint64_t count() const { return count_.load(std::memory_order_relaxed); }

  // The q-quantile, as the upper edge of its bin, s; 0 when empty.
  double Quantile(double q) const {
    const auto wanted = static_cast<uint64_t>(std::ceil(q * static_cast<double>(count())));
    uint64_t seen = 0;
    for (int i = 0; i < kBins; ++i) {
      seen += bins_[i].load(std::memory_order_relaxed);
      if (seen >= wanted && seen > 0) return (i + 1) * kBinSeconds;
    }
    return 0.0;
  }

 private:
  std::unique_ptr<std::atomic<uint64_t>[]> bins_ = std::make_unique<std::atomic<uint64_t>[]>(kBins);
  std::atomic<uint64_t> count_{0};
};

}  // namespace flsd
