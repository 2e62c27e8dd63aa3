#pragma once
// `flsd eval`: every skill rolled out once with the deterministic policy (its mean action), and
// the paper's metrics computed over the trajectories.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "skills/learning/networks/actor_critic.h"
#include "skills/learning/evaluation/metrics.h"
#include "skills/learning/networks/normalizer.h"
#include "skills/learning/runners/train_config.h"

namespace flsd {

struct EvaluationOptions {
  bool randomize = false;  // keep the training randomisation (and pushes) on
  int steps = 0;           // per skill; 0: the config's episode length
  uint64_t seed = 1;
};

Evaluation EvaluateSkills(const TrainConfig& config, ActorCritic policy, RunningNormalizer normalizer,
                          const EvaluationOptions& options);

// EvaluateSkills from `starts` seeds (options.seed, options.seed + 1, ...): the first one's
// record (trajectories, velocities, joint speeds, coverage), with each skill's survival the
// shortest of all its starts, and fell if it fell in any. One randomised start per skill misses
// skills that fall one time in three. `starts` must be at least 1.
Evaluation EvaluateWorstOfStarts(const TrainConfig& config, ActorCritic policy, RunningNormalizer normalizer,
                                 const EvaluationOptions& options, int starts);

nlohmann::json EvaluationJson(const Evaluation& evaluation);
// One row per skill: survival, mean velocities, height, gait frequency, high-frequency ratio.
std::string SkillSummaryCsv(const Evaluation& evaluation);

// Loads a run folder's config and checkpoint (the latest, or the one kept at `iteration`),
// evaluates, writes eval.json and eval_skills.csv (eval_ITER.json... for a kept one) into the
// run folder and returns the JSON.
nlohmann::json EvaluateRun(const std::string& run_dir, const EvaluationOptions& options, int iteration = 0);

}  // namespace flsd
