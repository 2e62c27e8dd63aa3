#include "skills/learning/networks/motion_history.h"

#include <algorithm>

#include "core/check.h"

namespace flsd {

MotionHistory::MotionHistory(int window) : window_(window), ring_((window - 1) * kMotionObsSize, 0.0f) {
  FLSD_DEMAND(window >= 1);
}

void MotionHistory::Restart(const float* frame) {
  for (int slot = 0; slot < window_ - 1; ++slot) {
    std::copy(frame, frame + kMotionObsSize, &ring_[slot * kMotionObsSize]);
  }
  head_ = 0;
}

void MotionHistory::Push(const float* frame) {
  if (window_ == 1) return;
  std::copy(frame, frame + kMotionObsSize, &ring_[head_ * kMotionObsSize]);
  head_ = (head_ + 1) % (window_ - 1);
}

void MotionHistory::WriteWindow(const float* newest, float* out) const {
  for (int t = 0; t < window_; ++t) {
    const float* frame =
        t == window_ - 1 ? newest : &ring_[((head_ + t) % (window_ - 1)) * kMotionObsSize];
    for (int c = 0; c < kMotionObsSize; ++c) out[c * window_ + t] = frame[c];
  }
}

}  // namespace flsd
