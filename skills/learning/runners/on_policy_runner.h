#pragma once
// rsl_rl's OnPolicyRunner: PPO on one task (rollout_task.h). The runner owns the learner (policy,
// normaliser, PPO, rollout storage), the collection loop, the run's counters, checkpoints,
// progress rows and the job's ranks; the task owns its environment.
//
// With several ranks in `comm` (data-parallel training under MPI), each rank's task steps its
// share of the job's envs, and the ranks average every gradient and merge the normaliser's
// statistics, so that all hold the same parameters. The figures are the whole job's.

#include <torch/torch.h>

#include <atomic>
#include <functional>
#include <string>

#include "skills/learning/runners/communicator.h"
#include "skills/learning/runners/policy_learner.h"
#include "skills/learning/runners/rollout_task.h"
#include "skills/learning/runners/run_folder.h"

namespace flsd {

// How long a run trains and how often it checkpoints: every `checkpoint_every` iterations and at
// the end, keeping a copy every `keep_every` iterations (0: none).
struct LearnSchedule {
  int iterations = 0;
  int checkpoint_every = 1;
  int keep_every = 0;
  std::function<void(int iteration)> after_keep;  // the leader's, after each checkpoint it keeps
};

class OnPolicyRunner {
 public:
  // `task` outlives the runner. `seed` is the run's; it draws the random streams of a rank that
  // resumes a checkpoint written by another rank layout.
  OnPolicyRunner(RolloutTask& task, const PpoConfig& ppo, uint64_t seed, const Communicator& comm = Communicator::Self());
  OnPolicyRunner(const OnPolicyRunner&) = delete;
  OnPolicyRunner& operator=(const OnPolicyRunner&) = delete;

  // One iteration: collect a rollout, let the task finish it, update PPO (on the mirror images too
  // when the task asks), then the task's own networks.
  RunnerStats RunIteration();

  // Iterates until schedule.iterations or a stop request, appending a progress row and logging a
  // line per iteration, and checkpointing as scheduled. Returns 0, or 3 when a loss turned
  // non-finite (the last good checkpoint is kept as it was). Every rank iterates and only the
  // leader writes; a stop requested on any rank stops them all after the same iteration.
  int Learn(const RunFolder& folder, const LearnSchedule& schedule, const std::atomic<bool>& stop_requested);

  // A checkpoint holds the learner's part (policy, normaliser, optimiser, counters, random state),
  // the task's streams and the task's own part; it is written atomically. With several ranks only
  // the leader should save. A checkpoint resumes with any number of ranks; the random streams are
  // restored only in one process resuming a one-process checkpoint (and otherwise drawn afresh
  // from the seed, the rank and the iteration). Loading a checkpoint that does not fit throws
  // InputError naming it.
  void SaveCheckpoint(const std::string& path) const;
  void LoadCheckpoint(const std::string& path);

  int iteration() const { return learner_.iteration(); }
  long env_steps() const { return learner_.env_steps(); }
  RunningNormalizer normalizer() const { return learner_.normalizer(); }
  const Communicator& communicator() const { return comm_; }

 private:
  void Collect(RunnerStats& stats);
  // The actor's normalised observations of this step.
  torch::Tensor Observe(bool update_normalizer);

  RolloutTask& task_;
  const Communicator& comm_;
  std::shared_ptr<PpoPolicyImpl> policy_;
  PolicyLearner learner_;
  Rollout& rollout_;         // the learner's
  torch::Tensor raw_obs_;    // [N, obs] this step's unnormalised observations
  torch::Tensor raw_rollout_obs_;  // [T, N, obs] the rollout's, when the task trains on mirror images
  torch::Tensor last_values_;      // [N] (or [N, S]) V after the last step
};

}  // namespace flsd
