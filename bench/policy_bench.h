#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace flsd {

struct PolicyBenchOptions {
  std::string library = "models/a1_flsd.safetensors";
  int calls = 20000;            // Eigen calls; libtorch gets a tenth as many
  double loop_seconds = 10.0;   // the real-time control loop, standing then running skill 0
};

// The serving policy at batch 1: PolicyRunner (Eigen) against libtorch on the same weights,
// with their largest output difference; then skilld's control loop (sim backend, real time)
// for loop_seconds, with its tick-start lateness (jitter) p50/p99 and deadline misses, and in the
// same run the jitter of a bare sleeping thread with the same scheduling: the machine's floor.
nlohmann::json RunPolicyBenchmark(const PolicyBenchOptions& options);

}  // namespace flsd
