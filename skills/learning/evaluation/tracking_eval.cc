#include "skills/learning/evaluation/tracking_eval.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include <yaml-cpp/yaml.h>

#include "core/rng.h"
#include "robot/observation.h"
#include "sim/env.h"

namespace flsd {

std::vector<TrackingCase> StandardTrackingCases() {
  return {{"stand", {0.0, 0.0, 0.0}},     {"forward", {0.5, 0.0, 0.0}},    {"backward", {-0.5, 0.0, 0.0}},
          {"left", {0.0, 0.5, 0.0}},      {"right", {0.0, -0.5, 0.0}},     {"turn_left", {0.0, 0.0, 1.0}},
          {"turn_right", {0.0, 0.0, -1.0}}, {"forward_turning", {0.5, 0.0, 0.5}}};
}

std::vector<TrackingCase> EvaluationTrackingCases(const SkillLibrary& library) {
  std::vector<TrackingCase> cases = StandardTrackingCases();
  const NearestSkillSelector dependable(library);
  Rng rng(kTrackingCaseSeed);
  for (int i = 0; i < kDrawnTrackingCases; ++i) {
    char name[16];
    std::snprintf(name, sizeof(name), "drawn_%02d", i);
    TrackingCase c{name, {}};
    for (int a = 0; a < 3; ++a) {
      c.command[a] = Uniform(rng, std::min(0.0, dependable.velocity_min()[a]), std::max(0.0, dependable.velocity_max()[a]));
    }
    cases.push_back(c);
  }
  return cases;
}

TrackingError TrackingErrorOf(const std::array<double, 3>& achieved, const std::array<double, 3>& command) {
  return {std::hypot(achieved[0] - command[0], achieved[1] - command[1]), std::abs(achieved[2] - command[2])};
}

namespace {

// The library's skills under one of its selectors.
class SelectorController final : public TrackingController {
 public:
  SelectorController(const SkillLibrary& library, SelectorKind kind) : policy_(library, kind) {}
  void Reset() override { policy_.Reset(); }
  std::array<double, 3> Clip(const double* command) const override { return policy_.Clip(command); }
  int Act(const float* motion_obs, const double* command, const float* previous_action, float* action) override {
    return policy_.Act(motion_obs, command, previous_action, action);
  }

 private:
  HierarchicalPolicy policy_;
};

}  // namespace

TrackingEvaluation EvaluateTracking(const SkillLibrary& library, const EnvConfig& env_config,
                                    const std::vector<TrackingCase>& cases, double seconds, double settle_seconds,
                                    uint64_t seed, SelectorKind selector) {
  SelectorController controller(library, selector);
  TrackingEvaluation out = EvaluateController(controller, ServedEnvConfig(library, env_config, 0), cases, seconds,
                                              settle_seconds, seed);
  out.selector = selector;
  return out;
}

TrackingEvaluation EvaluateController(TrackingController& controller, const EnvConfig& served,
                                      const std::vector<TrackingCase>& cases, double seconds, double settle_seconds,
                                      uint64_t seed) {
  const int steps = static_cast<int>(std::lround(seconds / a1::kControlDt));
  const int settle = static_cast<int>(std::lround(settle_seconds / a1::kControlDt));
  EnvConfig config = served;
  config.episode_steps = steps + 1;
  const MjModelPtr model = LoadMjModel(config.model);

  TrackingEvaluation out;
  out.seconds = seconds;
  out.settle_seconds = settle_seconds;
  double lin2 = 0.0, ang2 = 0.0;
  for (const TrackingCase& c : cases) {
    Env env(*model, config, seed);
    env.Reset();
    controller.Reset();
    TrackingResult r;
    r.tracked = {c.name, controller.Clip(c.command.data())};
    std::array<float, kMotionObsSize> motion{};
    std::array<float, kActionSize> previous{}, action{};
    std::set<int> used;
    int last_skill = -1, switches = 0, measured = 0;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int t = 0; t < steps; ++t) {
      BuildMotionObservation(env.state(), motion.data());
      const int skill = controller.Act(motion.data(), r.tracked.command.data(), previous.data(), action.data());
      used.insert(skill);
      if (skill != last_skill) r.holds.push_back({skill, t});
      switches += last_skill >= 0 && skill != last_skill;
      last_skill = skill;
      previous = action;
      const Termination ending = env.Step(action.data());
      ++r.steps;
      if (t >= settle) {
        const RobotState& s = env.state();
        sum += Eigen::Vector3d(s.base_linear_velocity.x(), s.base_linear_velocity.y(), s.base_angular_velocity.z());
        ++measured;
      }
      if (IsFailure(ending)) {
        r.fell = true;
        break;
      }
    }
    if (measured > 0) sum /= measured;
    r.achieved = {sum.x(), sum.y(), sum.z()};
    const TrackingError error = TrackingErrorOf(r.achieved, c.command);
    r.lin_error = error.lin;
    r.ang_error = error.ang;
    r.skills_used = static_cast<int>(used.size());
    r.switches_per_s = switches / (r.steps * a1::kControlDt);
    lin2 += r.lin_error * r.lin_error;
    ang2 += r.ang_error * r.ang_error;
    out.falls += r.fell;
    out.switches_per_s += r.switches_per_s / cases.size();
    out.cases.push_back(r);
  }
  out.rms_lin_error = std::sqrt(lin2 / out.cases.size());
  out.rms_ang_error = std::sqrt(ang2 / out.cases.size());
  return out;
}

nlohmann::json TrackingJson(const TrackingEvaluation& e) {
  nlohmann::json cases = nlohmann::json::array();
  for (const TrackingResult& r : e.cases) {
    cases.push_back({{"name", r.tracked.name},
                     {"command", r.tracked.command},
                     {"achieved", r.achieved},
                     {"lin_error", r.lin_error},
                     {"ang_error", r.ang_error},
                     {"steps", r.steps},
                     {"fell", r.fell},
                     {"skills_used", r.skills_used},
                     {"switches_per_s", r.switches_per_s},
                     {"holds", r.holds}});
  }
  return {{"selector", ToString(e.selector)},
          {"seconds", e.seconds},           {"settle_seconds", e.settle_seconds}, {"rms_lin_error", e.rms_lin_error},
          {"rms_ang_error", e.rms_ang_error}, {"falls", e.falls},                {"switches_per_s", e.switches_per_s},
          {"cases", cases}};
}

EnvConfig TrainingEnvOf(const SkillLibrary& library) {
  // The first policy's (a composed library's parts share the target filter; compose_library.h).
  const nlohmann::json& training = library.policies().front().training;
  const YAML::Node config = YAML::Load(training.at("config").get<std::string>());
  EnvConfig env;
  if (config["env"]) ReadConfig(config["env"], library.path() + ": training config: env.", env);
  return env;
}

EnvConfig ServedEnvConfig(const EnvConfig& env, int steps) {
  EnvConfig config = env;
  config.randomization.DisableAll();
  config.reset.standing_fraction = 1.0;  // skilld starts a skill or a velocity from a stand
  config.episode_steps = steps;
  return config;
}

EnvConfig ServedEnvConfig(const SkillLibrary& library, const EnvConfig& env, int steps) {
  EnvConfig config = ServedEnvConfig(env, steps);
  config.action_filter_hz = library.action_filter_hz();
  config.action_filter_order = library.action_filter_order();
  return config;
}

nlohmann::json CompareSelectors(const SkillLibrary& library, const std::vector<TrackingCase>& cases, double seconds,
                                double settle_seconds, uint64_t seed) {
  const EnvConfig env = TrainingEnvOf(library);
  nlohmann::json out = {{"library", library.path()}};
  out["learned"] = library.selector()
                       ? TrackingJson(EvaluateTracking(library, env, cases, seconds, settle_seconds, seed, SelectorKind::kLearned))
                       : nlohmann::json();
  for (SelectorKind analytic : {SelectorKind::kNearestSkill, SelectorKind::kTimeSharing}) {
    out[ToString(analytic)] = TrackingJson(EvaluateTracking(library, env, cases, seconds, settle_seconds, seed, analytic));
  }
  return out;
}

}  // namespace flsd
