#include "skills/learning/evaluation/transition_eval.h"

#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "core/check.h"
#include "robot/observation.h"
#include "sim/env.h"
#include "skills/learning/evaluation/tracking_eval.h"
#include "skills/runtime/nearest_skill.h"
#include "skills/runtime/selector.h"
#include "skills/runtime/safetensors.h"

namespace flsd {
namespace {

// Runs `skill` for `steps` control steps from the env's state: the step it fell at, or -1 if it
// did not. With `mean`, writes the mean body velocity (vx, vy, wz) of the steps from `settle` on.
int RunSkill(Env& env, PolicyRunner& runner, int skill, int steps, std::array<float, kActionSize>& previous,
             int settle = 0, std::array<double, 3>* mean = nullptr) {
  std::array<float, kMotionObsSize> motion{};
  std::array<float, kActionSize> action{};
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int t = 0; t < steps; ++t) {
    BuildMotionObservation(env.state(), motion.data());
    runner.Act(motion.data(), previous.data(), skill, action.data());
    previous = action;
    if (IsFailure(env.Step(action.data()))) return t;
    if (t >= settle) {
      const RobotState& s = env.state();
      sum += Eigen::Vector3d(s.base_linear_velocity.x(), s.base_linear_velocity.y(), s.base_angular_velocity.z());
    }
  }
  if (mean && steps > settle) {
    sum /= steps - settle;
    *mean = {sum.x(), sum.y(), sum.z()};
  }
  return -1;
}

}  // namespace

TransitionEvaluation EvaluateTransitions(const SkillLibrary& library, const EnvConfig& env_config, double first_seconds,
                                         double second_seconds, double settle_seconds, uint64_t seed, int handovers) {
  FLSD_DEMAND(handovers >= 1);
  auto steps_of = [](double seconds) { return static_cast<int>(std::lround(seconds / a1::kControlDt)); };
  const int first = steps_of(first_seconds), second = steps_of(second_seconds), settle = steps_of(settle_seconds);
  const int spacing = steps_of(kHandoverSpacing);
  const EnvConfig config = ServedEnvConfig(library, env_config, first + (handovers - 1) * spacing + second + 1);
  const MjModelPtr model = LoadMjModel(config.model);
  PolicyRunner runner(library);

  TransitionEvaluation out;
  out.first_seconds = first_seconds;
  out.second_seconds = second_seconds;
  out.settle_seconds = settle_seconds;
  out.handovers = handovers;
  out.skills = NearestSkillSelector(library).candidates();
  out.falls_into.assign(out.skills.size(), 0);
  std::vector<int> sources{-1};  // the stand, then every skill
  sources.insert(sources.end(), out.skills.begin(), out.skills.end());
  for (size_t j = 0; j < out.skills.size(); ++j) {
    const int to = out.skills[j];
    for (int from : sources) {
      if (from == to) continue;
      TransitionResult r{from, to};
      // From the stand there is no stride to be in: one start.
      for (int h = 0; h < (from >= 0 ? handovers : 1) && !r.fell; ++h) {
        Env env(*model, config, seed);
        env.Reset();
        std::array<float, kActionSize> previous{};
        std::array<double, 3> achieved{};
        r.fell = (from >= 0 && RunSkill(env, runner, from, first + h * spacing, previous) >= 0) ||
                 RunSkill(env, runner, to, second, previous, settle, &achieved) >= 0;
        if (h == 0) r.achieved = achieved;
      }
      if (from >= 0) {
        ++out.pairs;
        out.falls += r.fell;
        out.falls_into[j] += r.fell;
      }
      out.results.push_back(r);
    }
  }
  return out;
}

nlohmann::json TransitionJson(const TransitionEvaluation& e) {
  nlohmann::json results = nlohmann::json::array(), into = nlohmann::json::object();
  for (const TransitionResult& r : e.results) {
    results.push_back({{"from", r.from < 0 ? nlohmann::json("stand") : nlohmann::json(r.from)},
                       {"to", r.to},
                       {"fell", r.fell},
                       {"achieved", r.achieved}});
  }
  for (size_t j = 0; j < e.skills.size(); ++j) into[std::to_string(e.skills[j])] = e.falls_into[j];
  return {{"first_seconds", e.first_seconds},
          {"second_seconds", e.second_seconds},
          {"handovers", e.handovers},
          {"settle_seconds", e.settle_seconds},
          {"skills", e.skills},
          {"pairs", e.pairs},
          {"falls", e.falls},
          {"fall_share", e.pairs > 0 ? static_cast<double>(e.falls) / e.pairs : 0.0},
          {"falls_into", into},
          {"results", results}};
}

void RecordTransitions(const std::string& path, const std::vector<TransitionEvaluation>& evaluations) {
  FLSD_DEMAND(!evaluations.empty());
  SafeTensors file = ReadSafeTensors(path);
  nlohmann::json metadata = nlohmann::json::parse(file.metadata.at("flsd"));
  std::set<std::pair<int, int>> fell;
  nlohmann::json first_seconds = nlohmann::json::array();
  for (const TransitionEvaluation& e : evaluations) {
    first_seconds.push_back(e.first_seconds);
    for (const TransitionResult& r : e.results) {
      if (r.from >= 0 && r.fell) fell.insert({r.from, r.to});
    }
  }
  nlohmann::json falls = nlohmann::json::array();
  for (const auto& [from, to] : fell) falls.push_back({from, to});
  const TransitionEvaluation& e = evaluations.front();
  metadata["transitions"] = {{"first_seconds", first_seconds},
                             {"second_seconds", e.second_seconds},
                             {"handovers", e.handovers},
                             {"pairs", e.pairs},
                             {"falls", falls}};
  file.metadata["flsd"] = metadata.dump();
  WriteCheckedLibrary(path, file);
}

CycleEvaluation EvaluateCycles(const SkillLibrary& library, const EnvConfig& env_config, int per_axis, int periods,
                               uint64_t seed) {
  FLSD_DEMAND(per_axis >= 1 && periods >= 1);
  const int hold = MakeSelector(library, SelectorKind::kTimeSharing)->hold_steps();
  const EnvConfig config = ServedEnvConfig(library, env_config, periods * TimeSharingSelector::kMaxCycle * hold + 1);
  const MjModelPtr model = LoadMjModel(config.model);
  PolicyRunner runner(library);
  TimeSharingSelector selector(library);
  FallingCycles fell;  // the library's record is measured again, not trusted
  selector.AvoidCycles(fell);
  const Eigen::Vector3d lo = selector.nearest().velocity_min(), hi = selector.nearest().velocity_max();
  const auto grid = [&](int axis, int i) {
    return per_axis == 1 ? 0.5 * (lo[axis] + hi[axis]) : lo[axis] + (hi[axis] - lo[axis]) * i / (per_axis - 1);
  };

  CycleEvaluation out;
  out.per_axis = per_axis;
  out.periods = periods;
  out.hold_seconds = hold * a1::kControlDt;
  std::set<std::vector<int>> played;  // cycles as entered from the stand
  while (out.rounds < kCycleRounds) {
    std::map<std::vector<int>, int> chosen;  // this round's new cycles -> grid commands
    for (int i = 0; i < per_axis * per_axis * per_axis; ++i) {
      const double command[3] = {grid(0, i % per_axis), grid(1, i / per_axis % per_axis), grid(2, i / per_axis / per_axis)};
      selector.Reset();
      selector.Choose(command);
      if (selector.cycle_length() < 2) continue;
      const std::vector<int> cycle(selector.cycle().begin(), selector.cycle().begin() + selector.cycle_length());
      if (!played.count(cycle)) ++chosen[cycle];
    }
    if (chosen.empty()) break;
    ++out.rounds;
    for (const auto& [cycle, commands] : chosen) {
      Env env(*model, config, seed);
      env.Reset();
      std::array<float, kActionSize> previous{};
      CycleResult r{cycle, commands};
      const int length = static_cast<int>(cycle.size());
      for (int h = 0; h < periods * length && r.fell_at_step < 0; ++h) {
        const int fell = RunSkill(env, runner, cycle[h % length], hold, previous);
        if (fell >= 0) r.fell_at_step = h * hold + fell;
      }
      if (r.fell_at_step >= 0) {
        ++out.falls;
        fell.Add(cycle.data(), length);
        selector.AvoidCycles(fell);
      }
      played.insert(cycle);
      out.results.push_back(r);
    }
  }
  return out;
}

nlohmann::json CycleJson(const CycleEvaluation& e) {
  nlohmann::json results = nlohmann::json::array();
  for (const CycleResult& r : e.results) {
    results.push_back({{"skills", r.skills},
                       {"commands", r.commands},
                       {"fell_at_step", r.fell_at_step >= 0 ? nlohmann::json(r.fell_at_step) : nlohmann::json()}});
  }
  return {{"per_axis", e.per_axis},       {"periods", e.periods}, {"hold_seconds", e.hold_seconds},
          {"rounds", e.rounds},           {"cycles", e.results.size()}, {"falls", e.falls},
          {"results", results}};
}

void RecordCycles(const std::string& path, const CycleEvaluation& e) {
  SafeTensors file = ReadSafeTensors(path);
  nlohmann::json metadata = nlohmann::json::parse(file.metadata.at("flsd"));
  nlohmann::json falls = nlohmann::json::array();
  for (const CycleResult& r : e.results) {
    if (r.fell_at_step >= 0) falls.push_back(r.skills);
  }
  metadata["cycles"] = {{"per_axis", e.per_axis},
                        {"periods", e.periods},
                        {"hold_seconds", e.hold_seconds},
                        {"played", e.results.size()},
                        {"falls", falls}};
  file.metadata["flsd"] = metadata.dump();
  WriteCheckedLibrary(path, file);
}

}  // namespace flsd
