#pragma once
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace flsd {

struct SimBenchOptions {
  std::string config;  // YAML file with an `env` section; empty: the defaults (randomisation on)
  int num_envs = 64;
  int num_threads = 0;  // 0: every core
  double seconds = 6.0;  // timed per side, split over three alternating rounds
  uint64_t seed = 1;
};

// Runs the VecEnv with uniform random actions in [-1, 1] and, in the same run, on the same threads
// and alternating with it, two bare loops of mj_step (a PD torque toward a random target set once
// per control step, a copy back to the start state after a fall, nothing else):
// - physics_ceiling_steps_per_s: the same simulations as the VecEnv (each env's own randomised
//   model, one mjData each), so `ratio` is what the env layer costs on top of MuJoCo;
// - single_model_ceiling_steps_per_s: one nominal A1 per thread, all in cache, so
//   `ratio_vs_single_model` also counts what holding num_envs simulations in memory costs.
// Rates are control steps per second (mj_step rate / 4); mj_step_us is the cache-hot step cost.
nlohmann::json RunSimBenchmark(const SimBenchOptions& options);

class VecEnv;
// The physics ceiling of `vec`: control steps per second of the bare loop above over the same
// simulations (each env's own model and current state) on vec's threads, timed for `seconds`.
double MeasurePhysicsCeiling(VecEnv& vec, double seconds, uint64_t seed);

}  // namespace flsd
