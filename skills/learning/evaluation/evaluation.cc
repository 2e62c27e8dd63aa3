#include "skills/learning/evaluation/evaluation.h"

#include <filesystem>
#include <fstream>

#include "core/atomic_file.h"
#include "core/check.h"
#include "robot/observation.h"
#include "skills/learning/evaluation/library_bar.h"
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

namespace {

std::string BestFile(const std::string& run_dir) { return (std::filesystem::path(run_dir) / "best.json").string(); }

nlohmann::json ReadJsonFile(const std::string& path) {
  std::ifstream in(path);
  nlohmann::json json = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded() || !json.is_object()) throw InputError(path + ": expected a JSON object");
  return json;
}

}  // namespace

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

nlohmann::json JudgeKeptCheckpoint(const std::string& run_dir, int iteration) {
  EvaluationOptions options;
  options.randomize = true;
  const nlohmann::json eval = EvaluateRun(run_dir, options, iteration, kRandomizedStarts);
  const std::string path = BestFile(run_dir);
  nlohmann::json best = nlohmann::json::object();
  if (std::filesystem::exists(path)) best = ReadJsonFile(path);
  nlohmann::json judged = best.value("judged", nlohmann::json::array());
  // A resumed run judges again the checkpoints it keeps again: the latest judgement stands.
  for (auto it = judged.begin(); it != judged.end();) it = it->at("iteration") == iteration ? judged.erase(it) : it + 1;
  judged.push_back({{"iteration", iteration}, {"env_steps", eval.at("env_steps")}, {"bar", eval.at("bar")}});
  // The best of all judged, the earliest among equals.
  const nlohmann::json* chosen = nullptr;
  LibraryBar chosen_bar;
  for (const nlohmann::json& entry : judged) {
    const LibraryBar bar = LibraryBarFromJson(entry.at("bar"), path + " (iteration " + entry.at("iteration").dump() + ")");
    if (chosen == nullptr || BetterLibrary(bar, chosen_bar)) {
      chosen = &entry;
      chosen_bar = bar;
    }
  }
  best["iteration"] = chosen->at("iteration");
  best["env_steps"] = chosen->value("env_steps", nlohmann::json());
  best["bar"] = chosen->at("bar");
  best["rule"] = "every kept checkpoint judged over " + std::to_string(kRandomizedStarts) +
                 " randomised starts; best: all skills surviving, then directions within the limits, survivors, "
                 "directions, least slip";
  best["judged"] = judged;
  WriteFileAtomically(path, best.dump(2) + "\n");
  return best;
}

int BestIteration(const std::string& run_dir) {
  const std::string path = BestFile(run_dir);
  if (!std::filesystem::exists(path)) {
    throw InputError(run_dir + " has no best.json: the run judged none of its kept checkpoints (keep_best, "
                     "keep_checkpoint_every)");
  }
  const nlohmann::json best = ReadJsonFile(path);
  if (!best.contains("iteration") || !best.at("iteration").is_number_integer()) {
    throw InputError(path + ": expected an integer 'iteration'");
  }
  return best.at("iteration").get<int>();
}

}  // namespace flsd
