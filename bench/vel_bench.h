#pragma once
#include <nlohmann/json.hpp>

#include <string>

namespace flsd {

struct VelBenchOptions {
  std::string library = "models/a1_flsd.safetensors";
  std::string server_config;  // skilld's --config; empty: skilld's own default (configs/server.yaml)
  double seconds = 4.0;         // each command is held this long
  double settle_seconds = 1.0;  // and measured after this
  std::string cases = "standard";  // or "evaluation": the 40 of EvaluationTrackingCases
  int domain_id = 44;
};

// Velocity tracking as a user gets it: the eight commands of `flsd track` (stand, forward,
// backward, left, right, turn left, turn right, forward while turning; or the fixed evaluation
// set of 40 that begins with them) sent to a real skilld
// (simulated A1, the library and the selector it serves) as `track_velocity` calls, each from a
// fresh reset. The achieved velocity is the mean body velocity on the state topic after the settle
// time. Per command the errors; over them the RMS errors, the safety stops, and how many commands
// hold within 0.2 m/s and 0.3 rad/s. Then the skills the shipping bar counts for its six
// directions (forward, backward, left, right at 0.4 m/s or more, turning left and right in place
// at 1 rad/s or more; null where the library has none), each run for the same time as
// `execute_skill` from a fresh reset: whether each moves as its descriptor says, within 25 %.
nlohmann::json RunVelBenchmark(const VelBenchOptions& options);

}  // namespace flsd
