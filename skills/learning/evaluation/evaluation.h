#pragma once
// `flsd eval`: every skill of a run rolled out once with the deterministic policy (its mean
// action), and the paper's metrics computed over the trajectories (skill_rollouts.h).

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "skills/learning/networks/actor_critic.h"
#include "skills/learning/evaluation/metrics.h"
#include "skills/learning/evaluation/skill_rollouts.h"
#include "skills/learning/networks/normalizer.h"
#include "skills/learning/runners/train_config.h"

namespace flsd {

Evaluation EvaluateSkills(const TrainConfig& config, ActorCritic policy, RunningNormalizer normalizer,
                          const EvaluationOptions& options);

// Loads a run folder's config and checkpoint (the latest, or the one kept at `iteration`),
// evaluates from `starts` seeds (EvaluateOverStarts), writes eval.json and eval_skills.csv
// (eval_ITER.json... for a kept one, ..._startsN... for several starts) into the run folder and
// returns the JSON.
nlohmann::json EvaluateRun(const std::string& run_dir, const EvaluationOptions& options, int iteration = 0,
                           int starts = 1);

}  // namespace flsd
