#pragma once
// The last stage of the control convention between a policy's action and the motors: a low-pass
// filter on the joint targets, run once per control step. Training (Env) and serving
// (Controller) both run this class, with the cutoff and order the skill library records.
//
// Why: a PD motor fed a new target every 20 ms can be made to buzz at 10-25 Hz, and a buzzing
// robot creeps across the floor without stepping (docs/experiments.md). Filtering the targets
// takes that band away from the motors, as Peng et al. 2020 did for the Laikago.
//
// Order 1 is the exponential filter y += (1 - exp(-2 pi fc dt)) (x - y). Order 2 is a
// Butterworth filter discretised by the bilinear transform with the cutoff prewarped: at 10 Hz it
// passes a 3 Hz gait almost whole (gain 0.998, where order 1 at 4 Hz gives 0.805) and cuts a
// 20 Hz buzz harder (0.056 against 0.258).

#include "robot/a1.h"

namespace flsd {

class TargetFilter {
 public:
  // cutoff_hz 0 passes targets through unchanged. Throws InputError unless 0 <= cutoff_hz <=
  // the control rate's Nyquist frequency (25 Hz; order 2 needs it strictly below) and order is
  // 1 or 2.
  explicit TargetFilter(double cutoff_hz = 0.0, int order = 1);

  // The filter restarts at rest on `targets` (the measured joint positions when a policy takes
  // over, so that the first command does not jump).
  void Reset(const a1::JointArray<double>& targets);

  // One control step.
  const a1::JointArray<double>& Apply(const a1::JointArray<double>& targets);

  static constexpr double kMaxCutoffHz = 0.5 / a1::kControlDt;

 private:
  // y[n] = b0 x[n] + b1 x[n-1] + b2 x[n-2] - a1 y[n-1] - a2 y[n-2]; order 1 leaves b1..a2 at 0
  // but a1.
  double b0_ = 1.0, b1_ = 0.0, b2_ = 0.0, a1_ = 0.0, a2_ = 0.0;
  a1::JointArray<double> x1_ = a1::kDefaultJointPos, x2_ = a1::kDefaultJointPos;
  a1::JointArray<double> y2_ = a1::kDefaultJointPos;
  a1::JointArray<double> output_ = a1::kDefaultJointPos;  // y[n-1], then y[n]
};

}  // namespace flsd
