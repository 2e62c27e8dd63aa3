#pragma once
#include <nlohmann/json.hpp>

#include <string>

namespace flsd {

struct NavBenchOptions {
  std::string library = "models/a1_flsd.safetensors";
  std::string server_config;  // skilld's --config; empty: skilld's own default (configs/server.yaml)
  int goals = 3;  // per map
  int seed = 1;
  int domain_id = 43;
  double min_distance = 3.0;  // m between a start and its goal
};

// Navigation as a user gets it: a real skilld (simulated A1, the library, its selector) started
// for the run, driven over DDS on loopback. For every shipped map (configs/maps), `goals` random
// start and goal pairs with a path between them; before each the robot is reset, and the map is
// sent shifted so that the reset pose is the start. Per map: the success rate, the time to the
// goal against the planned path's length over the library's top speed (the ideal), the replans,
// and the closest approach of the robot's centre to an obstacle (negative: it walked into one).
nlohmann::json RunNavBenchmark(const NavBenchOptions& options);

}  // namespace flsd
