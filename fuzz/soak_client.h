#pragma once
// One client of the soak bench (flsd bench soak): for a while, random requests of
// RandomRequests from a few client ids, each reply checked by ReplyOracle, and the calls whose
// effect the state topic shows (damp, acquire_control, release_control) checked there too.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

#include "comm/security_config.h"

namespace flsd::fuzz {

struct SoakClientOptions {
  int domain_id = 0;
  std::string partition;
  dds::SecurityConfig security;  // on: every request of this client comes from its identity
  std::string name = "soak0";    // prefix of its client ids
  uint64_t seed = 1;
  double seconds = 60.0;
  double rate_hz = 50.0;         // requests per second
  bool heavy_maps = true;
  bool can_reset = true;         // false for skilld --backend hw
  double lease_timeout = 0.0;    // s, skilld's, from its config (required: the oracle has no guess)
  double max_duration = 0.0;     // s, skilld's: the longest motion it accepts
};

// Runs the client; its tally as JSON: requests, answered, dropped, late (replies that came after
// their request was counted dropped), wrong (with up to 5 examples), statuses, damp_latency_ms
// (every damp sent while the robot was not damped: from the request to the first state sample
// showing the robot damped, by the two clocks of this machine), state_checks, and the last
// state's requests_dropped.
nlohmann::json RunSoakClient(const SoakClientOptions& options);

}  // namespace flsd::fuzz
