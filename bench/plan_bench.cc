#include "bench/plan_bench.h"

#include <cmath>
#include <vector>

#include "bench/machine.h"
#include "bench/stats.h"
#include "server/navigation/path_planner.h"

namespace flsd {
namespace {

struct Case {
  const char* map;
  Eigen::Vector2d start, goal;
};

}  // namespace

nlohmann::json RunPlanBenchmark(const PlanBenchOptions& options) {
  const std::vector<Case> cases = {
      {"open", {-3.0, -2.0}, {3.0, 2.0}},
      {"wall_gap", {-3.0, 0.0}, {3.0, 0.0}},
      {"demo", {0.0, 0.0}, {5.0, 0.5}},
  };
  nlohmann::json maps = nlohmann::json::array();
  for (const Case& c : cases) {
    const Map2D map = Map2D::Load(std::string("configs/maps/") + c.map + ".yaml");
    std::vector<double> first_ms, full_ms, ratio;
    int failures = 0;
    for (int trial = 0; trial < options.trials; ++trial) {
      PlannerOptions first;
      first.first_solution_only = true;
      const PlannedPath quick = PlanPath(map, c.start, c.goal, first);
      const PlannedPath best = PlanPath(map, c.start, c.goal, PlannerOptions{});
      if (quick.status != PlannedPath::Status::kFound || best.status != PlannedPath::Status::kFound) {
        ++failures;
        continue;
      }
      first_ms.push_back(quick.planning_seconds * 1e3);
      full_ms.push_back(best.planning_seconds * 1e3);
      ratio.push_back(best.length / (c.goal - c.start).norm());
    }
    maps.push_back({{"map", c.map},
                    {"trials", options.trials},
                    {"failures", failures},
                    {"first_path_ms_p50", Quantile(first_ms, 0.5)},
                    {"first_path_ms_p99", Quantile(first_ms, 0.99)},
                    {"full_call_ms_p50", Quantile(full_ms, 0.5)},
                    {"full_call_ms_p99", Quantile(full_ms, 0.99)},
                    {"length_over_straight_line_p50", Quantile(ratio, 0.5)},
                    {"length_over_straight_line_max", Quantile(ratio, 1.0)}});
  }
  // The wall map's shortest path is known in closed form (tests/server/navigation/path_planner_test.cc).
  const double d = std::hypot(2.9, 1.4), r = 0.35;
  const double wall_optimum = 2.0 * (std::sqrt(d * d - r * r) + r * (std::atan2(1.4, 2.9) + std::asin(r / d))) + 0.2;
  return {{"benchmark", "flsd bench plan"},
          {"planner", "OMPL InformedRRT*, 0.5 s, then simplification"},
          {"maps", maps},
          {"wall_gap_optimum_over_straight_line", wall_optimum / 6.0},
          {"machine", MachineDescription()}};
}

}  // namespace flsd
