#pragma once
// What an on-policy task gives the runner (rsl_rl's VecEnv, widened to the task's own learning):
// the policy it trains and its action space, each step's observations, rewards and ends, the
// rollout's batched rewards and terminations, its auxiliary updates (the PAE and the
// discriminator of skill discovery), its part of a checkpoint and its progress columns. The runner
// (on_policy_runner.h) owns the loop, PPO, the normaliser, the rollout and the run's counters.

#include <torch/torch.h>

#include <memory>
#include <string>
#include <vector>

#include "core/rng.h"
#include "skills/learning/algorithms/ppo.h"
#include "skills/learning/networks/normalizer.h"
#include "skills/learning/runners/communicator.h"
#include "skills/learning/runners/policy_learner.h"
#include "skills/learning/runners/progress_log.h"

namespace flsd {

// What the runner measures in every iteration, whatever the task.
struct RunnerStats {
  int iteration = 0;
  long env_steps = 0;        // since the run began, over every rank
  double steps_per_s = 0.0;  // env steps over the whole iteration's wall time
  PpoStats ppo;
  bool finite = true;        // PPO's loss and the task's auxiliary losses
  // Wall seconds: observing and the policy's forward passes, the whole collection (those and the
  // task's steps), the task's end of rollout, PPO, the iteration. The task times its own parts.
  double seconds_policy = 0.0, seconds_collect = 0.0, seconds_finish = 0.0, seconds_ppo = 0.0,
         seconds_total = 0.0;
  Communicator::Tally collectives;  // MPI collectives within the iteration (none in one process)
};

class RolloutTask {
 public:
  virtual ~RolloutTask() = default;

  // The network PPO trains: the task chooses the action space (joint targets, or one of a
  // library's skills). Built before the runner, so that every network draws its initial weights
  // from the seed in the task's order.
  virtual std::shared_ptr<PpoPolicyImpl> policy() const = 0;
  // This rank's rollout: steps per iteration, envs, and the observation and action sizes.
  virtual RolloutShape shape() const = 0;
  // How many leading columns of the actor's observation the runner normalises.
  virtual int normalized_obs() const = 0;
  // Control steps (20 ms) one rollout step simulates in each env: more than one for a decision
  // that holds a skill.
  virtual int control_steps_per_step() const { return 1; }
  // Train on the rollout's left-right mirror images too (Mirror).
  virtual bool mirrored() const = 0;

  // A rollout: BeginRollout, then per step t Observe, CriticObservations and Step, then Observe and
  // CriticObservations once more (for the values to bootstrap from), then FinishRollout.
  virtual void BeginRollout() {}
  // Writes every env's unnormalised actor observation into `raw` [envs, obs].
  virtual void Observe(torch::Tensor& raw) = 0;
  // The critic's observations [envs, critic_obs] from the actor's normalised ones.
  virtual torch::Tensor CriticObservations(const torch::Tensor& obs) { return obs; }
  // Acts on `actions` (the policy's samples, [envs, action]) and writes step t's rewards, dones and
  // time-outs into `rollout`.
  virtual void Step(int t, const torch::Tensor& actions, Rollout& rollout) = 0;
  // After the last step: rewards computed over the whole rollout, terminations that rewrite the
  // dones, and the task's figures summed over every rank. `iteration`: the runner's, before this one.
  virtual void FinishRollout(Rollout& rollout, int iteration) = 0;
  // With mirrored(): the rollout's mirror images; `raw_obs` [T * N, obs] are the unnormalised
  // actor observations.
  virtual MirroredSamples Mirror(const torch::Tensor& raw_obs, const Rollout& rollout,
                                 const RunningNormalizer& normalizer) const = 0;
  // After PPO's update: the task's own networks learn from the rollout. False when a loss was
  // not finite.
  virtual bool UpdateAuxiliaries() { return true; }

  // The per-env random streams (skill or command draws) that a checkpoint keeps, their key in it,
  // and the seed a rank draws them afresh from when it resumes another rank layout.
  virtual std::vector<Rng>& env_streams() = 0;
  virtual const char* env_streams_key() const = 0;
  virtual uint64_t env_streams_seed() const = 0;
  // The task's own part of a checkpoint (its config, its networks and optimisers). Load throws
  // InputError or c10::Error when the checkpoint does not fit.
  virtual void Save(torch::serialize::OutputArchive& archive) const = 0;
  virtual void Load(torch::serialize::InputArchive& archive, const std::string& path) = 0;

  // The last iteration's progress.csv columns, the runner's figures among them, and its line for
  // the terminal.
  virtual ProgressRecord Progress(const RunnerStats& runner) const = 0;
  virtual std::string ProgressLine(const RunnerStats& runner, int total_iterations, double eta_seconds) const = 0;
};

}  // namespace flsd
