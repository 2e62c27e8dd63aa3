#pragma once
// What an evaluation keeps of every skill's rollout, and the Evaluation made of it. Shared by the
// two ways a skill is rolled out: by the policy a run trains (flsd eval, libtorch) and by a
// library as skilld runs it (flsd eval-library, Eigen). Plain C++.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "robot/observation.h"
#include "sim/env.h"
#include "skills/learning/evaluation/metrics.h"

namespace flsd {

struct EvaluationOptions {
  bool randomize = false;  // keep the training randomisation (and pushes) on
  int steps = 0;           // per skill; 0: the config's episode length
  uint64_t seed = 1;
  // With randomize: every skill starts from the default pose at rest, as skilld starts one from a
  // stand, rather than from the training's tossed reset (joints scaled, the base thrown); the
  // physics and the pushes stay randomised. Tells a skill's falls from the toss from the rest.
  // Last, so that {randomize, steps, seed} initialisers keep their meaning.
  bool standing_start = false;
  bool RandomizedFromStand() const { return randomize && standing_start; }
};

// The env a skill is evaluated in: the training env, made nominal unless options.randomize (its
// start untossed also with options.standing_start), and
// one step longer than the record (`steps`), so that no episode times out inside it.
EnvConfig EvaluationEnvConfig(const EnvConfig& training, const EvaluationOptions& options);
int EvaluationSteps(const EnvConfig& training, const EvaluationOptions& options);

// Every skill's trajectory up to its first termination, and what the velocity task's reward needs
// of each of its steps.
class SkillRollouts {
 public:
  SkillRollouts(int skills, int steps);

  // Before the first step: the state the velocity task's reward starts from.
  void Start(int skill, const RobotState& state);
  // After one control step of `skill` with `action`: keeps the env's state unless the step ended
  // the rollout (a failed state is not part of the skill). Returns whether the skill runs on.
  bool Record(int skill, const Env& env, Termination ending, const float* action, bool calf_contact);

  // The paper's metrics over the trajectories, and each skill's velocity-task reward.
  Evaluation Finish(const std::string& method, bool randomized, std::vector<int> mirror_skill) const;

 private:
  struct TaskStep {
    RobotState state;
    std::array<float, kActionSize> action;
    bool calf_contact;
  };
  // legged_gym's velocity-task reward per second, term by term, that skill k earns when the
  // command is its own mean velocity (VelocityRewardConfig: the A1's scales).
  VelocityRewardTerms TaskReward(std::size_t k, const SkillSummary& skill) const;

  int steps_;
  std::vector<SkillTrajectory> trajectories_;
  std::vector<RobotState> start_;
  std::vector<std::vector<TaskStep>> task_steps_;
  std::vector<bool> running_;
};

// Randomised starts per skill in an exported library's evaluation (EvaluateOverStarts). From one
// start, postures that fall in 3 of 7 starts passed.
inline constexpr int kRandomizedStarts = 8;

// `evaluate` from `starts` seeds (options.seed, options.seed + 1, ...): the first one's record
// (trajectories, velocities, joint speeds, coverage), with each skill's survival the shortest of
// its starts, fell if it fell in any, and its stance-foot slip the mean of its starts. One
// randomised start misses skills that fall one time in three, and moves a skill's slip by up to
// 0.13 m/s. `starts` must be at least 1.
Evaluation EvaluateOverStarts(const EvaluationOptions& options, int starts,
                              const std::function<Evaluation(const EvaluationOptions&)>& evaluate);

nlohmann::json EvaluationJson(const Evaluation& evaluation);
// One row per skill: survival, mean velocities, height, gait frequency, high-frequency ratio.
std::string SkillSummaryCsv(const Evaluation& evaluation);

}  // namespace flsd
