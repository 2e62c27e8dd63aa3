#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace flsd {

struct TrainBenchOptions {
  std::string config = "configs/flsd_cpu.yaml";
  std::string method;  // empty: the config's
  int iterations = 4;  // timed, after one warm-up iteration
  int threads = 0;     // > 0: simulation threads per process instead of the config's
};

// Runs whole iterations of Algorithm 1 (rollout, rewards, PPO, PAE and discriminator updates)
// and, alternating with them on the same threads, the physics ceiling of the same simulations.
// Prints env_steps_per_s, physics_ceiling_steps_per_s, ratio, and where an iteration's time goes.
// Under mpirun every rank runs its share and the figures are the job's (the leader's JSON; the
// other ranks return null), with the time and bytes of the MPI collectives per iteration.
nlohmann::json RunTrainBenchmark(const TrainBenchOptions& options);

struct MpiBenchOptions {
  TrainBenchOptions train;
  int ranks = 2;
};

// Data parallelism against threads on the same machine, in one command: `flsd bench train` as
// `ranks` MPI processes of one thread each (through mpirun) and as one process of `ranks` threads.
// Prints both and their throughput ratio (the target is at least 0.9).
nlohmann::json RunMpiBenchmark(const MpiBenchOptions& options);

}  // namespace flsd
