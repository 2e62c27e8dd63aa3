#include "robot/target_filter.h"

#include <cmath>
#include <string>

#include "core/check.h"

namespace flsd {

TargetFilter::TargetFilter(double cutoff_hz, int order) {
  if (order != 1 && order != 2) {
    throw InputError("action filter order: expected 1 or 2, got " + std::to_string(order));
  }
  const bool below_nyquist = order == 1 ? cutoff_hz <= kMaxCutoffHz : cutoff_hz < kMaxCutoffHz;
  if (!(cutoff_hz >= 0.0 && below_nyquist)) {
    throw InputError("action filter cutoff: expected 0 (off) to " + std::to_string(kMaxCutoffHz) + " Hz" +
                     (order == 2 ? " (exclusive) for order 2" : "") + ", got " + std::to_string(cutoff_hz));
  }
  if (cutoff_hz == 0.0) return;
  if (order == 1) {
    const double gain = 1.0 - std::exp(-2.0 * M_PI * cutoff_hz * a1::kControlDt);
    b0_ = gain;
    a1_ = gain - 1.0;
    return;
  }
  const double k = std::tan(M_PI * cutoff_hz * a1::kControlDt);
  const double norm = 1.0 / (1.0 + M_SQRT2 * k + k * k);
  b0_ = k * k * norm;
  b1_ = 2.0 * b0_;
  b2_ = b0_;
  a1_ = 2.0 * (k * k - 1.0) * norm;
  a2_ = (1.0 - M_SQRT2 * k + k * k) * norm;
}

void TargetFilter::Reset(const a1::JointArray<double>& targets) { x1_ = x2_ = y2_ = output_ = targets; }

const a1::JointArray<double>& TargetFilter::Apply(const a1::JointArray<double>& targets) {
  for (int j = 0; j < a1::kNumJoints; ++j) {
    const double y = b0_ * targets[j] + b1_ * x1_[j] + b2_ * x2_[j] - a1_ * output_[j] - a2_ * y2_[j];
    x2_[j] = x1_[j];
    x1_[j] = targets[j];
    y2_[j] = output_[j];
    output_[j] = y;
  }
  return output_;
}

}  // namespace flsd
