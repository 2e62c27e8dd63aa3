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

// A run's own rule for the checkpoint it offers as its library: each kept checkpoint is evaluated
// as `flsd export` judges one (kRandomizedStarts randomised starts: survival the worst, slip the
// mean), and the best by BetterLibrary is named in RUN/best.json with its bar, beside every kept
// checkpoint judged so far (how many it was picked from). Returns best.json's contents.
nlohmann::json JudgeKeptCheckpoint(const std::string& run_dir, int iteration);
// The iteration RUN/best.json names; throws InputError if the run has judged no checkpoint.
int BestIteration(const std::string& run_dir);

}  // namespace flsd
