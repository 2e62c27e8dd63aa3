#pragma once
// The reward of a semi-MDP skill selector (not the paper's, whose selector is paid legged_gym's
// per-step reward): tracking of the velocity averaged over the selector's memory window, with a
// smaller share of the instantaneous tracking, legged_gym's penalties as small terms, and a
// penalty for a fall. A per-step reward pays a cycle of holds whose mean is the command less than
// the nearest single skill (each hold is off the command); the window mean pays it more.

#include <Eigen/Core>

#include "core/config.h"

namespace flsd {

struct SelectorRewardConfig {
  // Seconds of the memory's window (SelectorMemory); 0 turns the semi-MDP selector off: the
  // selector sees o^c alone and is paid legged_gym's reward, as in the paper.
  double window_s = 0.0;
  double window_share = 0.8;  // of the tracking reward paid on the window's mean; the rest on each step
  // (m/s)^2 of exp(-|e|^2 / sigma), |e| with the yaw rate weighted by turn_weight: 0.1 m/s off
  // earns 0.90, 0.3 m/s 0.41, so that a command no skill reaches still pays for coming closer.
  double sigma = 0.1;
  // m/s that a yaw-rate error of 1 rad/s counts as in |e| (NearestSkillSelector::kTurnWeight's 0.5
  // weighs a turn as the skills' choice does; the evaluation reports the two errors apart).
  double turn_weight = 0.5;
  double penalty_scale = 0.02;  // times legged_gym's non-tracking terms (per second)
  double fall_penalty = 2.0;   // once, when the robot falls
  template <class V>
  void Visit(V& v) {
    v("window_s", window_s, Bounds<double>{0.0, 60.0});
    v("window_share", window_share, Bounds<double>{0.0, 1.0});
    v("sigma", sigma, Bounds<double>{1e-4, 10.0});
    v("turn_weight", turn_weight, Bounds<double>{0.0, 10.0});
    v("penalty_scale", penalty_scale, Bounds<double>{0.0, 100.0});
    v("fall_penalty", fall_penalty, Bounds<double>{0.0, 1e3});
  }
  bool enabled() const { return window_s > 0.0; }
};

// The reward per second of one control step: `window_error` and `error` are command minus the
// window's mean and minus this step's (vx, vy, wz); `penalties_per_s` legged_gym's scaled
// non-tracking terms.
double SelectorRewardPerSecond(const SelectorRewardConfig& config, const Eigen::Vector3d& window_error,
                               const Eigen::Vector3d& error, double penalties_per_s);

}  // namespace flsd
