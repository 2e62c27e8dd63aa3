#pragma once
// Constraints as terminations (Chane-Sane et al., "CaT: Constraints as Terminations for Legged
// Locomotion", 2024): a step that violates a constraint ends the episode with a probability that
// grows with the violation, instead of paying a penalty that competes with the intrinsic reward
// (penalties as reward terms made every skill a still posture on our budget). The probability of
// constraint c is max_p_c * clip(violation_c / EMA of the batch's largest violation_c, 0, 1), a
// step's is the largest over the constraints, and the trainer scales the step's reward and the
// bootstrap of what follows by one minus it.

#include <torch/torch.h>

#include <array>
#include <string>

#include "core/config.h"
#include "sim/constraints.h"
#include "skills/learning/runners/communicator.h"

namespace flsd {

struct ConstraintTerminationConfig {
  // The soft constraints' max_p ramps linearly from the first to the second value over
  // ramp_iterations (CaT's curriculum: 0.05 to 0.25 over 1000 iterations), counted from the first
  // iteration that ran with constraints, so a run fine-tuned from an unconstrained checkpoint gets
  // the whole curriculum too.
  Interval max_p{0.05, 0.25};
  int ramp_iterations = 1000;
  // A knee on the floor is a hard constraint, as CaT's body contacts: it always ends the episode.
  double calf_contact_max_p = 1.0;
  // The stance-foot slip's max_p is the soft constraints' times this (at most 1): a run can press
  // on slip harder than on the rest, whose full CaT probabilities stop every skill.
  double foot_slip_factor = 1.0;
  // With a start of 0 the factor holds from the first constrained iteration; otherwise it ramps in
  // linearly from 1 over ramp_iterations, starting this many iterations after that one: pressure on
  // slip from the start keeps skills from learning to walk, so a run can let its movers appear first.
  int foot_slip_start = 0;
  double ema_decay = 0.95;  // of the batch's largest violation, per constraint
  template <class V>
  void Visit(V& v) {
    v("max_p", max_p, Bounds<double>{0.0, 1.0});
    v("ramp_iterations", ramp_iterations, Bounds<int>{0, 100000000});
    v("calf_contact_max_p", calf_contact_max_p, Bounds<double>{0.0, 1.0});
    v("foot_slip_factor", foot_slip_factor, Bounds<double>{0.0, 1e3});
    v("foot_slip_start", foot_slip_start, Bounds<int>{0, 100000000});
    v("ema_decay", ema_decay, Bounds<double>{0.0, 1.0});
  }
};

// What one rollout's constraints did, over all ranks.
struct ConstraintStats {
  std::array<double, kNumConstraints> violation_rate{};  // share of steps with a violation
  double mean_probability = 0.0;                         // mean termination probability per step
};

class ConstraintTerminations {
 public:
  explicit ConstraintTerminations(const ConstraintTerminationConfig& config) : config_(config) {}

  // violations [T, N, kNumConstraints] (sim/constraints.h) -> termination probabilities [T, N] at
  // training iteration `iteration`; updates the running scales with every rank's batch.
  torch::Tensor Probabilities(const torch::Tensor& violations, int iteration, const Communicator& comm,
                              ConstraintStats& stats);

  // The first constrained iteration and the running scales, for checkpoints ("" before any batch).
  std::string State() const;
  void Restore(const std::string& state, const std::string& where);

 private:
  double MaxP(int constraint, int iteration) const;
  // 0 to 1 over ramp_iterations, from `delay` iterations after the first constrained one.
  double RampProgress(int iteration, int delay) const;

  ConstraintTerminationConfig config_;
  int first_iteration_ = -1;                     // the ramp's start; -1 before any batch
  std::array<double, kNumConstraints> scale_{};  // EMA of the largest violation; 0 before any
};

}  // namespace flsd
