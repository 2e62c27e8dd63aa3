#pragma once
#include <nlohmann/json.hpp>

#include <string>

namespace flsd {

struct SoakBenchOptions {
  double minutes = 10.0;
  int clients = 4;             // soak_client processes
  std::string backend = "sim"; // hw: skilld drives the robot emulator, which injects faults
  bool security = false;       // DDS Security: a PKI of its own (scripts/make_pki.sh), one identity per client
  bool beside_training = false;  // `flsd train` on configs/smoke.yaml with 1 thread all along
  bool heavy_maps = true;
  double rate_hz = 50.0;       // requests per second of each client
  std::string library = "models/a1_flsd.safetensors";
  int domain_id = 0;
  uint64_t seed = 1;
};

// A real skilld under random valid and invalid calls of `clients` processes for `minutes`, each
// reply checked by fuzz::ReplyOracle (and the state topic): wrong replies, crashes, requests
// unanswered; skilld's memory, descriptors and threads from the first minute on; its tick lateness
// and deadline misses (from its exit line); the time from a damp request to the state showing it.
nlohmann::json RunSoakBenchmark(const SoakBenchOptions& options);

}  // namespace flsd
