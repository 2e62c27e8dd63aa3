#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace flsd {

struct TrainBenchOptions {
  std::string config = "configs/flsd_cpu.yaml";
  std::string method;  // empty: the config's
  int iterations = 4;  // timed, after one warm-up iteration
};

// Runs whole iterations of Algorithm 1 (rollout, rewards, PPO, PAE and discriminator updates)
// and, alternating with them on the same threads, the physics ceiling of the same simulations.
// Prints env_steps_per_s, physics_ceiling_steps_per_s, ratio, and where an iteration's time goes.
nlohmann::json RunTrainBenchmark(const TrainBenchOptions& options);

}  // namespace flsd
