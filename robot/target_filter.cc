#include "robot/target_filter.h"

#include <cmath>
#include <string>

#include "core/check.h"

namespace flsd {

TargetFilter::TargetFilter(double cutoff_hz) {
  if (!(cutoff_hz >= 0.0 && cutoff_hz <= kMaxCutoffHz)) {
    throw InputError("action filter cutoff: expected 0 (off) to " + std::to_string(kMaxCutoffHz) + " Hz, got " +
                     std::to_string(cutoff_hz));
  }
  gain_ = cutoff_hz == 0.0 ? 1.0 : 1.0 - std::exp(-2.0 * M_PI * cutoff_hz * a1::kControlDt);
}

const a1::JointArray<double>& TargetFilter::Apply(const a1::JointArray<double>& targets) {
  for (int j = 0; j < a1::kNumJoints; ++j) output_[j] += gain_ * (targets[j] - output_[j]);
  return output_;
}

}  // namespace flsd
