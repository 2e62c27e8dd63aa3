#pragma once
// The arithmetic of one iteration's learning phases, to read each phase's time against the
// machine's own GEMM rate: a phase near that rate is at the hardware's limit, one far below it is
// spending its time on something other than arithmetic (per-call overhead, memory traffic).

#include "skills/learning/tasks/skill_discovery_task.h"

namespace flsd {

// GFLOP of the last iteration's phases: 2 per multiply-accumulate of every linear layer and
// convolution (the rest is small beside them), a backward pass counted as twice its forward.
struct LearningArithmetic {
  double policy_inference = 0.0;  // actor and critic on every step
  double rewards = 0.0;           // PAE encoding of every window (and its mirror), discriminator
  double ppo_update = 0.0;
  double pae_update = 0.0;
  double discriminator_update = 0.0;
};
LearningArithmetic ArithmeticOfLastIteration(const SkillDiscoveryTask& task);

// Single-precision n x n GEMM through libtorch (the BLAS and threads that training uses), repeated
// for `seconds`: GFLOP/s.
double MeasureSgemmGflops(int n, double seconds);

}  // namespace flsd
