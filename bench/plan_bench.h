#pragma once
#include <nlohmann/json.hpp>

namespace flsd {

struct PlanBenchOptions {
  int trials = 20;  // per map
};

// OMPL planning on the shipped maps (configs/maps), between fixed start and goal pairs: the time
// to the first path (p50, p99), the time of a full planning call, and the path length after it
// over the straight line between start and goal (a lower bound; the wall map's true optimum is
// known and given too).
nlohmann::json RunPlanBenchmark(const PlanBenchOptions& options);

}  // namespace flsd
