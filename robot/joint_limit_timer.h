#pragma once
// How long each joint has kept breaking a limit. skilld's supervisor stops the robot by it
// (server/safety.h), training ends an episode by it (sim/env.h) and `flsd eval` reports a skill's
// longest overspeed by it (skills/learning/evaluation/metrics.h): one rule, so that a skill is trained and
// judged by the limits it is served under.

#include <algorithm>
#include <cmath>

#include "robot/a1.h"

namespace flsd {

class JointLimitTimer {
 public:
  // Adds dt to each joint j for which breaking(j) holds and clears the others. Returns Longest().
  template <class Breaking>
  double Update(Breaking breaking, double dt) {
    for (int j = 0; j < a1::kNumJoints; ++j) seconds_[j] = breaking(j) ? seconds_[j] + dt : 0.0;
    return Longest();
  }
  // The longest time any joint has now held it, s.
  double Longest() const { return *std::max_element(seconds_.begin(), seconds_.end()); }
  void Reset() { seconds_.fill(0.0); }

 private:
  a1::JointArray<double> seconds_{};
};

// True once a limit has held for longer than `tolerance` s. The slack keeps a whole number of
// ticks that sums to the tolerance from tripping early.
inline bool Outlasts(double seconds, double tolerance) { return seconds > tolerance + 1e-9; }

// The A1's speed limit as a breaking rule; NaN breaks it.
inline auto FasterThan(const a1::JointArray<double>& velocity, double limit) {
  return [&velocity, limit](int j) { return !(std::abs(velocity[j]) <= limit); };
}

}  // namespace flsd
