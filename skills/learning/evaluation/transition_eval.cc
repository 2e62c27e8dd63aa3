#include "skills/learning/evaluation/transition_eval.h"

#include <set>
#include <utility>

#include <cmath>

#include "core/check.h"
#include "robot/observation.h"
#include "sim/env.h"
#include "skills/learning/evaluation/tracking_eval.h"
#include "skills/runtime/nearest_skill.h"
#include "skills/runtime/safetensors.h"

namespace flsd {
namespace {

// Runs `skill` for `steps` control steps from the env's state; false if the robot fell. With
// `mean`, writes the mean body velocity (vx, vy, wz) of the steps from `settle` on.
bool RunSkill(Env& env, PolicyRunner& runner, int skill, int steps, std::array<float, kActionSize>& previous,
              int settle = 0, std::array<double, 3>* mean = nullptr) {
  std::array<float, kMotionObsSize> motion{};
  std::array<float, kActionSize> action{};
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int t = 0; t < steps; ++t) {
    BuildMotionObservation(env.state(), motion.data());
    runner.Act(motion.data(), previous.data(), skill, action.data());
    previous = action;
    if (IsFailure(env.Step(action.data()))) return false;
    if (t >= settle) {
      const RobotState& s = env.state();
      sum += Eigen::Vector3d(s.base_linear_velocity.x(), s.base_linear_velocity.y(), s.base_angular_velocity.z());
    }
  }
  if (mean && steps > settle) {
    sum /= steps - settle;
    *mean = {sum.x(), sum.y(), sum.z()};
  }
  return true;
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
        r.fell = (from >= 0 && !RunSkill(env, runner, from, first + h * spacing, previous)) ||
                 !RunSkill(env, runner, to, second, previous, settle, &achieved);
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

}  // namespace flsd
