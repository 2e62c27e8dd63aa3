#include "bench/vel_bench.h"

#include <chrono>
#include <cmath>

#include "bench/machine.h"
#include "bench/skilld_process.h"
#include "core/check.h"
#include "skills/learning/evaluation/tracking_eval.h"

namespace flsd {
namespace {

constexpr double kLinearTolerance = 0.2;   // m/s
constexpr double kAngularTolerance = 0.3;  // rad/s

// One command from a fresh reset; the robot is stopped afterwards.
nlohmann::json Track(Client& client, const TrackingCase& c, const VelBenchOptions& options) {
  ResetAndWait(client);
  const Task task = client.TrackVelocity(c.command[0], c.command[1], c.command[2], options.seconds);
  nlohmann::json result = {{"name", c.name}, {"command", c.command}};
  if (!task.accepted()) {
    result["outcome"] = "refused";
    result["message"] = task.reply().Describe();
    return result;
  }
  result["reply"] = task.reply().message;  // says so when the command was clipped to the library's envelope
  std::array<double, 3> sum{};
  int samples = 0;
  bool tripped = false;  // a safety stop: a fall, or a limit broken
  uint64_t tick = 0;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.seconds + 10.0);
  while (!task.Done() && std::chrono::steady_clock::now() < give_up) {
    const std::optional<StateReport> state = client.NextState(tick, std::chrono::milliseconds(500));
    if (!state) continue;
    tick = state->tick;
    if (state->task.request_id != task.request_id()) continue;
    tripped = tripped || state->faults != 0;
    if (state->mode != Mode::kVelocity || state->task.elapsed < options.settle_seconds) continue;
    sum[0] += state->linear_velocity[0];
    sum[1] += state->linear_velocity[1];
    sum[2] += state->angular_velocity[2];
    ++samples;
  }
  const TaskReport report = task.Progress();
  client.Stop();
  result["outcome"] = Name(report.state);
  result["message"] = report.message;
  result["safety_stop"] = tripped || report.state == TaskState::kSafetyStop;
  if (samples == 0) return result;
  const std::array<double, 3> achieved = {sum[0] / samples, sum[1] / samples, sum[2] / samples};
  const TrackingError error = TrackingErrorOf(achieved, c.command);
  result["achieved"] = achieved;
  result["samples"] = samples;
  result["lin_error"] = error.lin;
  result["ang_error"] = error.ang;
  result["holds"] = error.lin <= kLinearTolerance && error.ang <= kAngularTolerance;
  return result;
}

}  // namespace

nlohmann::json RunVelBenchmark(const VelBenchOptions& options) {
  if (!(options.settle_seconds >= 0.0 && options.settle_seconds < options.seconds)) {
    throw InputError("--settle must be at least 0 and below --seconds");
  }
  SkilldProcess skilld(options.library, options.server_config, options.domain_id, "velbench");
  const std::unique_ptr<Client> client = skilld.Connect();
  nlohmann::json cases = nlohmann::json::array();
  double lin2 = 0.0, ang2 = 0.0;
  int measured = 0, held = 0, safety_stops = 0;
  for (const TrackingCase& c : StandardTrackingCases()) {
    nlohmann::json result = Track(*client, c, options);
    if (result.contains("lin_error")) {
      lin2 += std::pow(result["lin_error"].get<double>(), 2);
      ang2 += std::pow(result["ang_error"].get<double>(), 2);
      ++measured;
      held += result["holds"].get<bool>();
    }
    safety_stops += result.value("safety_stop", false);
    cases.push_back(std::move(result));
  }
  const int count = static_cast<int>(cases.size());
  return {{"benchmark", "flsd bench vel"},
          {"library", options.library},
          {"seconds", options.seconds},
          {"settle_seconds", options.settle_seconds},
          {"cases", cases},
          {"measured", measured},
          {"rms_lin_error", measured > 0 ? nlohmann::json(std::sqrt(lin2 / measured)) : nlohmann::json()},
          {"rms_ang_error", measured > 0 ? nlohmann::json(std::sqrt(ang2 / measured)) : nlohmann::json()},
          {"safety_stops", safety_stops},
          {"held", held},
          {"held_ratio", static_cast<double>(held) / count},
          {"tolerance", {{"lin", kLinearTolerance}, {"ang", kAngularTolerance}}},
          {"machine", MachineDescription()}};
}

}  // namespace flsd
