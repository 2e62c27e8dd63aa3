#include "bench/vel_bench.h"

#include <chrono>
#include <cmath>

#include "bench/machine.h"
#include "bench/skilld_process.h"
#include "core/check.h"
#include "core/paths.h"
#include "skills/learning/evaluation/library_bar.h"
#include "skills/learning/evaluation/tracking_eval.h"

namespace flsd {
namespace {

constexpr double kLinearTolerance = 0.2;   // m/s
constexpr double kAngularTolerance = 0.3;  // rad/s
// A skill moves as its descriptor says when its measured velocity (vx, vy), or for a turn its yaw
// rate, is within this share of the descriptor's: at most 25 % off in speed, and at most
// asin(0.25) = 14 degrees off in direction.
constexpr double kDescribedShare = 0.25;

// What the state topic showed while `task` ran in `mode`: the mean body velocity (vx, vy, wz)
// after the settle time, whether a safety limit tripped, and how the task ended. The robot is
// stopped afterwards.
struct Motion {
  std::array<double, 3> mean{};
  int samples = 0;
  bool safety_stop = false;
  TaskReport report;
};

Motion Measure(Client& client, const Task& task, Mode mode, const VelBenchOptions& options) {
  Motion motion;
  std::array<double, 3> sum{};
  uint64_t tick = 0;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.seconds + 10.0);
  while (!task.Done() && std::chrono::steady_clock::now() < give_up) {
    const std::optional<StateReport> state = client.NextState(tick, std::chrono::milliseconds(500));
    if (!state) continue;
    tick = state->tick;
    if (state->task.request_id != task.request_id()) continue;
    motion.safety_stop = motion.safety_stop || state->faults != 0;
    if (state->mode != mode || state->task.elapsed < options.settle_seconds) continue;
    sum[0] += state->linear_velocity[0];
    sum[1] += state->linear_velocity[1];
    sum[2] += state->angular_velocity[2];
    ++motion.samples;
  }
  motion.report = task.Progress();
  client.Stop();
  motion.safety_stop = motion.safety_stop || motion.report.state == TaskState::kSafetyStop;
  for (int i = 0; motion.samples > 0 && i < 3; ++i) motion.mean[i] = sum[i] / motion.samples;
  return motion;
}

// One command from a fresh reset.
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
  const Motion motion = Measure(client, task, Mode::kVelocity, options);
  result["outcome"] = Name(motion.report.state);
  result["message"] = motion.report.message;
  result["safety_stop"] = motion.safety_stop;
  if (motion.samples == 0) return result;
  const TrackingError error = TrackingErrorOf(motion.mean, c.command);
  result["achieved"] = motion.mean;
  result["samples"] = motion.samples;
  result["lin_error"] = error.lin;
  result["ang_error"] = error.ang;
  result["holds"] = error.lin <= kLinearTolerance && error.ang <= kAngularTolerance;
  return result;
}

// The library's skill for `direction` (the one the shipping bar counts), run from a fresh reset
// as `execute_skill`, against its descriptor.
nlohmann::json RunDirectionSkill(Client& client, const SkillLibrary& library, int direction, int skill,
                                 const VelBenchOptions& options) {
  nlohmann::json result = {{"direction", kDirectionNames[direction]}};
  if (skill < 0) {
    result["skill"] = nullptr;
    result["as_described"] = false;
    return result;
  }
  const SkillDescriptor& d = library.skills()[skill];
  const std::array<double, 3> described = {d.mean_linear_velocity.x(), d.mean_linear_velocity.y(),
                                           d.mean_angular_velocity.z()};
  result["skill"] = skill;
  result["described"] = described;
  ResetAndWait(client);
  const Task task = client.ExecuteSkill(skill, options.seconds);
  if (!task.accepted()) {
    result["outcome"] = "refused";
    result["message"] = task.reply().Describe();
    result["as_described"] = false;
    return result;
  }
  const Motion motion = Measure(client, task, Mode::kSkill, options);
  result["outcome"] = Name(motion.report.state);
  result["safety_stop"] = motion.safety_stop;
  result["samples"] = motion.samples;
  const bool turn = direction == static_cast<int>(Direction::kTurnLeft) ||
                    direction == static_cast<int>(Direction::kTurnRight);
  const double off = turn ? std::abs(motion.mean[2] - described[2]) / std::abs(described[2])
                          : std::hypot(motion.mean[0] - described[0], motion.mean[1] - described[1]) /
                                std::hypot(described[0], described[1]);
  result["measured"] = motion.mean;
  result["relative_error"] = off;
  result["as_described"] = motion.samples > 0 && !motion.safety_stop &&
                           motion.report.state == TaskState::kSucceeded && off <= kDescribedShare;
  return result;
}

}  // namespace

nlohmann::json RunVelBenchmark(const VelBenchOptions& options) {
  if (!(options.settle_seconds >= 0.0 && options.settle_seconds < options.seconds)) {
    throw InputError("--settle must be at least 0 and below --seconds");
  }
  if (options.cases != "standard" && options.cases != "evaluation") {
    throw InputError("--cases '" + options.cases + "': expected standard or evaluation");
  }
  const SkillLibrary library = SkillLibrary::Load(ResolveDataPath(options.library));
  SkilldProcess skilld(options.library, options.server_config, options.domain_id, "velbench");
  const std::unique_ptr<Client> client = skilld.Connect();
  nlohmann::json cases = nlohmann::json::array();
  double lin2 = 0.0, ang2 = 0.0;
  int measured = 0, held = 0, safety_stops = 0;
  for (const TrackingCase& c : options.cases == "standard" ? StandardTrackingCases() : EvaluationTrackingCases(library)) {
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
  const std::array<int, kNumDirections> direction_skills = DirectionSkills(library);
  nlohmann::json skills = nlohmann::json::array();
  int as_described = 0;
  for (int d = 0; d < kNumDirections; ++d) {
    skills.push_back(RunDirectionSkill(*client, library, d, direction_skills[d], options));
    as_described += skills.back()["as_described"].get<bool>();
  }
  return {{"benchmark", "flsd bench vel"},
          {"library", options.library},
          {"seconds", options.seconds},
          {"settle_seconds", options.settle_seconds},
          {"case_set", options.cases},
          {"cases", cases},
          {"measured", measured},
          {"rms_lin_error", measured > 0 ? nlohmann::json(std::sqrt(lin2 / measured)) : nlohmann::json()},
          {"rms_ang_error", measured > 0 ? nlohmann::json(std::sqrt(ang2 / measured)) : nlohmann::json()},
          {"safety_stops", safety_stops},
          {"held", held},
          {"held_ratio", static_cast<double>(held) / count},
          {"tolerance", {{"lin", kLinearTolerance}, {"ang", kAngularTolerance}}},
          {"direction_skills", skills},
          {"direction_skills_as_described", as_described},
          {"direction_skills_ratio", static_cast<double>(as_described) / kNumDirections},
          {"described_share", kDescribedShare},
          {"machine", MachineDescription()}};
}

}  // namespace flsd
