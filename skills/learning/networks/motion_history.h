#pragma once
#include <vector>

#include "robot/observation.h"

namespace flsd {

// The motion observations o^m of one episode so far, for the PAE's windows o^H (H frames, the
// newest last). A new episode fills the history with its first frame (replicate padding), so a
// window never mixes two episodes.
class MotionHistory {
 public:
  explicit MotionHistory(int window);

  void Restart(const float* frame);  // kMotionObsSize floats
  void Push(const float* frame);

  // Writes the window that ends with `newest` (the H - 1 stored frames, then `newest`) as
  // [kMotionObsSize, H], channel-major, as Conv1d takes it.
  void WriteWindow(const float* newest, float* out) const;

 private:
  int window_;
  int head_ = 0;             // slot of the oldest stored frame
  std::vector<float> ring_;  // (H - 1) frames
};

}  // namespace flsd
