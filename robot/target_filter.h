#pragma once
// The last stage of the control convention between a policy's action and the motors: a
// first-order low-pass filter on the joint targets, run once per control step. Training (Env)
// and serving (Controller) both run this class, with the cutoff the skill library records.
//
// Why: a PD motor fed a new target every 20 ms can be made to buzz at 10-25 Hz, and a buzzing
// robot creeps across the floor without stepping (README, "Training runs"). Filtering the targets
// takes that band away from the motors, as Peng et al. 2020 did for the Laikago.

#include "robot/a1.h"

namespace flsd {

class TargetFilter {
 public:
  // cutoff_hz 0 passes targets through unchanged. Throws InputError unless 0 <= cutoff_hz <=
  // the control rate's Nyquist frequency (25 Hz).
  explicit TargetFilter(double cutoff_hz = 0.0);

  // The filter's output restarts at `targets` (the measured joint positions when a policy takes
  // over, so that the first command does not jump).
  void Reset(const a1::JointArray<double>& targets) { output_ = targets; }

  // One control step: moves the output toward `targets` by the fraction 1 - exp(-2 pi fc dt).
  const a1::JointArray<double>& Apply(const a1::JointArray<double>& targets);

  static constexpr double kMaxCutoffHz = 0.5 / a1::kControlDt;

 private:
  double gain_;  // the fraction of the remaining step taken per control step
  a1::JointArray<double> output_ = a1::kDefaultJointPos;
};

}  // namespace flsd
