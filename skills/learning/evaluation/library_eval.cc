#include "skills/learning/evaluation/library_eval.h"

#include "robot/observation.h"
#include "skills/learning/evaluation/tracking_eval.h"

namespace flsd {

Evaluation EvaluateLibrary(const SkillLibrary& library, const EvaluationOptions& options) {
  EnvConfig training = TrainingEnvOf(library);
  training.action_filter_hz = library.action_filter_hz();
  training.action_filter_order = library.action_filter_order();
  const EnvConfig config = EvaluationEnvConfig(training, options);
  const int steps = EvaluationSteps(training, options);
  const MjModelPtr model = LoadMjModel(config.model);
  PolicyRunner runner(library);
  const int skills = library.num_skills();
  SkillRollouts rollouts(skills, steps);
  std::vector<int> mirror_skill;
  for (int k = 0; k < skills; ++k) {
    mirror_skill.push_back(library.skills()[k].mirror_skill);
    Env env(*model, config, options.seed);
    env.Reset();
    rollouts.Start(k, env.state());
    std::array<float, kMotionObsSize> motion{};
    std::array<float, kActionSize> action{}, previous{};
    for (int t = 0; t < steps; ++t) {
      BuildMotionObservation(env.state(), motion.data());
      runner.Act(motion.data(), previous.data(), k, action.data());
      previous = action;
      const Termination ending = env.Step(action.data());
      if (!rollouts.Record(k, env, ending, action.data(), env.calf_contact())) break;
    }
  }
  return rollouts.Finish("library", options.randomize, std::move(mirror_skill));
}

}  // namespace flsd
