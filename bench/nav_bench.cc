#include "bench/nav_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <vector>

#include "bench/machine.h"
#include "bench/skilld_process.h"
#include "bench/stats.h"
#include "client/client.h"
#include "core/check.h"
#include "core/paths.h"
#include "core/rng.h"
#include "navigation_map/map2d.h"
#include "server/navigation/path_planner.h"
#include "server/server_config.h"
#include "skills/learning/evaluation/tracking_eval.h"
#include "skills/runtime/selector.h"
#include "skills/runtime/skill_library.h"

namespace flsd {
namespace {

namespace fs = std::filesystem;

struct Goal {
  Eigen::Vector2d start, goal;
  double shortest_length = 0.0;  // m, straight segments planned here: a path exists, and the ideal
};

// `count` start and goal pairs at least `min_distance` apart, both with 0.2 m of room beyond the
// robot's radius, and a path between them.
std::vector<Goal> DrawGoals(const Map2D& map, int count, double min_distance, Rng& rng) {
  std::vector<Goal> goals;
  const auto draw = [&] {
    return Eigen::Vector2d(Uniform(rng, map.x_min, map.x_max), Uniform(rng, map.y_min, map.y_max));
  };
  for (int attempt = 0; attempt < 2000 && static_cast<int>(goals.size()) < count; ++attempt) {
    const Eigen::Vector2d start = draw(), goal = draw();
    if ((goal - start).norm() < min_distance) continue;
    if (map.Clearance(start) < map.robot_radius + 0.2 || map.Clearance(goal) < map.robot_radius + 0.2) continue;
    PlannerOptions options;
    options.time_limit = 0.2;
    const PlannedPath path = PlanPath(map, start, goal, options);
    if (path.status == PlannedPath::Status::kFound) goals.push_back({start, goal, path.length});
  }
  return goals;
}

// The fastest forward speed that the selector skilld serves for navigate holds within
// kSteerTolerance, measured as `flsd track` measures (10 s from a stand in simulation, the mean
// after 2 s), in steps of kSteerStep down from the fastest dependable forward skill: what a path
// follower can ask for and get. 0 if it holds none.
constexpr double kSteerTolerance = 0.2;  // m/s
constexpr double kSteerStep = 0.05;      // m/s
double SteerableForwardSpeed(const SkillLibrary& library, SelectorKind kind, double forward_top_speed) {
  const EnvConfig env = TrainingEnvOf(library);
  for (double v = forward_top_speed; v > 0.0; v -= kSteerStep) {
    const TrackingEvaluation e = EvaluateTracking(library, env, {{"forward", {v, 0.0, 0.0}}}, 10.0, 2.0, kTrackingEnvSeed, kind);
    if (e.falls == 0 && e.rms_lin_error <= kSteerTolerance) return v;
  }
  return 0.0;
}

double PathLength(const std::vector<double>& flat) {
  double length = 0.0;
  for (size_t i = 2; i + 1 < flat.size(); i += 2) length += std::hypot(flat[i] - flat[i - 2], flat[i + 1] - flat[i - 1]);
  return length;
}

// One navigation from a fresh reset; the robot is stopped afterwards.
nlohmann::json Navigate(Client& client, const Map2D& map, const Goal& goal, double top_speed) {
  ResetAndWait(client);
  const Eigen::Vector2d local_goal = goal.goal - goal.start;
  const double ideal = goal.shortest_length / top_speed;
  const double duration = std::min(300.0, 20.0 + 4.0 * ideal);
  const Task task = client.Navigate(local_goal.x(), local_goal.y(), map.Shifted(goal.start).ToYaml(), duration);
  nlohmann::json result = {{"start", {goal.start.x(), goal.start.y()}}, {"goal", {goal.goal.x(), goal.goal.y()}}};
  if (!task.accepted()) {
    result["outcome"] = "refused";
    result["message"] = task.reply().Describe();
    return result;
  }
  // From the state topic at its full rate: the closest approach (in the map's own frame), the
  // first plan's length, and each new plan after it, a replan.
  double closest = HUGE_VAL, planned_length = 0.0;
  int replans = 0;
  std::vector<double> path;
  uint64_t tick = 0;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(duration + 15.0);
  while (!task.Done() && std::chrono::steady_clock::now() < give_up) {
    const std::optional<StateReport> state = client.NextState(tick, std::chrono::milliseconds(500));
    if (!state) continue;
    tick = state->tick;
    const Eigen::Vector2d p = goal.start + Eigen::Vector2d(state->position[0], state->position[1]);
    if (state->task.request_id == task.request_id() && state->mode == Mode::kNavigate) {
      closest = std::min(closest, map.Clearance(p));
      if (!state->task.path.empty() && state->task.path != path) {
        if (path.empty()) planned_length = PathLength(state->task.path);
        else ++replans;
        path = state->task.path;
      }
    }
  }
  const TaskReport report = task.Progress();
  client.Stop();
  result["outcome"] = Name(report.state);
  result["message"] = report.message;
  result["seconds"] = report.elapsed;
  result["shortest_length"] = goal.shortest_length;
  result["planned_length"] = planned_length;
  result["time_over_ideal"] = report.elapsed / ideal;
  result["replans"] = replans;
  if (std::isfinite(closest)) result["closest_approach"] = closest;
  return result;
}

}  // namespace

nlohmann::json RunNavBenchmark(const NavBenchOptions& options) {
  SkilldProcess skilld(options.library, options.server_config, options.domain_id, "navbench");
  const std::unique_ptr<Client> served = skilld.Connect();
  Client& client = *served;
  // The ideal speed: the fastest skill the server serves (the selector's choices); and the fastest
  // going forward, the way the follower walks, for a library whose top speed is backward.
  double top_speed = 0.0, forward_top_speed = 0.0;
  const SkillLibrary library = SkillLibrary::Load(ResolveDataPath(options.library));
  for (const SkillDescriptor& s : library.skills()) {
    if (!Dependable(s)) continue;
    const double speed = s.mean_linear_velocity.head<2>().norm();
    top_speed = std::max(top_speed, speed);
    if (s.mean_linear_velocity.x() > 0.0) forward_top_speed = std::max(forward_top_speed, speed);
  }
  if (!(top_speed > 0.0)) throw InputError(options.library + ": no dependable skill moves");
  const ServerConfig config =
      LoadServerConfig(ResolveDataPath(options.server_config.empty() ? "configs/server.yaml" : options.server_config));
  const std::optional<SelectorKind> selector =
      ServedSelectorKind(library, config.navigation.selector, SelectorKind::kNearestSkill);
  if (!selector) throw InputError(options.library + ": skilld serves no selector for navigate over it");
  const double steerable_speed = SteerableForwardSpeed(library, *selector, forward_top_speed);

  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(ResolveDataPath("configs/maps"))) {
    if (e.path().extension() == ".yaml") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  nlohmann::json maps = nlohmann::json::array();
  int all = 0, all_succeeded = 0;
  Rng rng(options.seed);
  for (const fs::path& file : files) {
    const Map2D map = Map2D::Load(file.string());
    const std::vector<Goal> goals = DrawGoals(map, options.goals, options.min_distance, rng);
    nlohmann::json runs = nlohmann::json::array();
    std::vector<double> ratios, forward_ratios, steerable_ratios, replans;
    double closest = HUGE_VAL;
    int succeeded = 0;
    for (const Goal& goal : goals) {
      nlohmann::json run = Navigate(client, map, goal, top_speed);
      if (run["outcome"] == "succeeded") {
        ++succeeded;
        ratios.push_back(run["time_over_ideal"]);
        if (forward_top_speed > 0.0) forward_ratios.push_back(ratios.back() * forward_top_speed / top_speed);
        if (steerable_speed > 0.0) steerable_ratios.push_back(ratios.back() * steerable_speed / top_speed);
      }
      if (run.contains("replans")) replans.push_back(run["replans"]);
      if (run.contains("closest_approach")) closest = std::min(closest, run["closest_approach"].get<double>());
      runs.push_back(std::move(run));
    }
    all += static_cast<int>(goals.size());
    all_succeeded += succeeded;
    nlohmann::json entry = {{"map", file.stem().string()},
                            {"goals", goals.size()},
                            {"success_rate", goals.empty() ? 0.0 : static_cast<double>(succeeded) / goals.size()},
                            {"time_over_ideal_p50", Quantile(ratios, 0.5)},
                            {"time_over_ideal_max", Quantile(ratios, 1.0)},
                            {"time_over_forward_ideal_p50", Quantile(forward_ratios, 0.5)},
                            {"time_over_forward_ideal_max", Quantile(forward_ratios, 1.0)},
                            {"time_over_steerable_ideal_p50", Quantile(steerable_ratios, 0.5)},
                            {"time_over_steerable_ideal_max", Quantile(steerable_ratios, 1.0)},
                            {"replans_mean", Mean(replans)},
                            {"closest_approach_min", std::isfinite(closest) ? nlohmann::json(closest) : nlohmann::json()},
                            {"runs", runs}};
    if (goals.empty()) entry["note"] = "no start and goal pair with a path between them";
    maps.push_back(std::move(entry));
  }
  return {{"benchmark", "flsd bench nav"},
          {"library", options.library},
          {"top_speed", top_speed},
          {"forward_top_speed", forward_top_speed},
          {"selector", ToString(*selector)},
          {"steerable_forward_speed", steerable_speed},
          {"steerable", "the fastest forward command (in 0.05 m/s steps) the navigate selector holds within 0.2 m/s "
                        "over 10 s from a stand in simulation"},
          {"ideal", "shortest path (straight segments) / top_speed (the fastest skill surviving 500 steps)"},
          {"success_rate", all == 0 ? 0.0 : static_cast<double>(all_succeeded) / all},
          {"maps", maps},
          {"machine", MachineDescription()}};
}

}  // namespace flsd
