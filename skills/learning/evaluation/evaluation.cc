#include "skills/learning/evaluation/evaluation.h"

#include <filesystem>

#include "core/atomic_file.h"
#include "robot/observation.h"
#include "core/thread_pool.h"
#include "sim/vec_env.h"
#include "skills/learning/runners/run_folder.h"
#include "skills/learning/tasks/skill_discovery_task.h"

namespace flsd {
Evaluation EvaluateSkills(const TrainConfig& config, ActorCritic policy, RunningNormalizer normalizer,
                          const EvaluationOptions& options) {
  torch::NoGradGuard no_grad;
  const int skills = config.num_skills;
  const int steps = EvaluationSteps(config.env, options);
  // One env per skill, stepped together; an env's record ends at its first termination.
  VecEnv vec(EvaluationEnvConfig(config.env, options), skills, options.seed, ResolveThreadCount(config.num_threads));
  SkillRollouts rollouts(skills, steps);
  for (int k = 0; k < skills; ++k) rollouts.Start(k, vec.env(k).state());
  const int obs_size = PolicyObservationSize(skills);
  torch::Tensor raw = torch::zeros({skills, obs_size});
  std::vector<float> previous(skills * kActionSize, 0.0f);
  for (int t = 0; t < steps; ++t) {
    for (int k = 0; k < skills; ++k) {
      BuildPolicyObservation(vec.motion_obs() + k * kMotionObsSize, &previous[k * kActionSize], k, skills,
                             raw.data_ptr<float>() + k * obs_size);
    }
    const torch::Tensor action = policy->ActionMean(NormalizeLeadingColumns(normalizer, raw)).contiguous();
    const float* a = action.data_ptr<float>();
    std::copy(a, a + skills * kActionSize, previous.begin());
    vec.Step(a);
    bool any = false;
    for (int k = 0; k < skills; ++k) {
      // A VecEnv resets an env that ended; the record keeps none of its states from then on.
      any |= rollouts.Record(k, vec.env(k), vec.termination()[k], a + k * kActionSize, vec.stepped_calf_contact(k));
    }
    if (!any) break;
  }
  const mirror::SkillPairing pairing = SkillPairingOf(skills, config.symmetry);
  std::vector<int> mirror_skill;
  for (int k = 0; k < skills; ++k) mirror_skill.push_back(pairing(k));
  return rollouts.Finish(config.method, options.randomize, std::move(mirror_skill));
}

nlohmann::json EvaluateRun(const std::string& run_dir, const EvaluationOptions& options, int iteration, int starts) {
  namespace fs = std::filesystem;
  const TrainConfig config = LoadTrainConfig((fs::path(run_dir) / "config.yaml").string());
  const TrainedPolicy trained = LoadTrainedPolicy(config, RunCheckpoint(run_dir, iteration));
  const Evaluation eval = EvaluateOverStarts(options, starts, [&](const EvaluationOptions& o) {
    return EvaluateSkills(config, trained.policy, trained.normalizer, o);
  });
  nlohmann::json json = EvaluationJson(eval);
  json["run"] = run_dir;
  json["iteration"] = trained.iteration;
  json["env_steps"] = trained.env_steps;
  json["standing_start"] = options.RandomizedFromStand();
  const std::string suffix =
      (iteration > 0 ? "_" + std::to_string(iteration) : std::string()) + (options.randomize ? "_randomized" : "") +
      (options.RandomizedFromStand() ? "_standing" : "") + (starts > 1 ? "_starts" + std::to_string(starts) : "");
  WriteFileAtomically((fs::path(run_dir) / ("eval" + suffix + ".json")).string(), json.dump(2) + "\n");
  WriteFileAtomically((fs::path(run_dir) / ("eval" + suffix + "_skills.csv")).string(), SkillSummaryCsv(eval));
  return json;
}

}  // namespace flsd
