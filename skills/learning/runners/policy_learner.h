#pragma once
// The learning half of the on-policy runner (on_policy_runner.h): the policy, its observation
// normaliser, PPO and the rollout it learns from, the run's counters, and their part of a
// checkpoint. The task (rollout_task.h) fills the rollout and keeps its own networks and random
// streams.

#include <torch/torch.h>

#include <memory>
#include <vector>

#include "core/rng.h"

#include "skills/learning/networks/actor_critic.h"
#include "skills/learning/runners/communicator.h"
#include "skills/learning/networks/normalizer.h"
#include "skills/learning/algorithms/ppo.h"

namespace flsd {

// The sizes of a rollout's tensors, each [steps, envs, ...].
struct RolloutShape {
  int steps = 0, envs = 0;
  int obs = 0, critic_obs = 0;  // critic_obs == obs: the critic reads the actor's observations
  int action = 0, distribution = 0;
  int value_streams = 1;
};

// This rank's share of a job's `total` envs; InputError unless every rank gets as many.
int LocalEnvCount(int total, const Communicator& comm);

// From the runner's constructor, once every network has drawn its initial weights from the seed
// (the same on every rank): each rank after the first draws its actions and minibatches from a
// stream of its own.
void SeedRankStreams(uint64_t seed, const Communicator& comm);

class PolicyLearner {
 public:
  // `normalized_obs` leading observation columns are normalised. `seed` draws the random streams
  // of a rank that resumes a checkpoint written by another rank layout.
  PolicyLearner(std::shared_ptr<PpoPolicyImpl> policy, int normalized_obs, const PpoConfig& config, uint64_t seed,
                const Communicator& comm);

  void AllocateRollout(const RolloutShape& shape);

  PpoPolicyImpl& policy() { return *policy_; }
  RunningNormalizer normalizer() const { return normalizer_; }
  Rollout& rollout() { return rollout_; }
  const Communicator& comm() const { return comm_; }

  // Adds this step's raw observations (every rank's) to the normaliser's statistics.
  void UpdateNormalizer(const torch::Tensor& raw);

  // GAE(lambda) over the rollout (advantages normalised over every rank's), then PPO on it and,
  // when given, on its mirror images. `last_values` are V of the observations after the last step.
  PpoStats Update(const torch::Tensor& last_values, const MirroredSamples* mirrored = nullptr);

  // One more iteration, of `job_steps` env steps over every rank.
  void CountIteration(long job_steps);
  int iteration() const { return iteration_; }
  long env_steps() const { return env_steps_; }

  // The learner's part of a checkpoint: policy, normaliser, optimiser, counters, learning rate,
  // rank count and libtorch's random state; and the task's per-env random streams under `key`.
  void Write(torch::serialize::OutputArchive& archive, const std::vector<Rng>& env_streams, const char* key) const;
  // Reads it back. The random streams are taken over only by one process resuming a one-process
  // checkpoint. Otherwise each rank draws afresh for this layout: libtorch's generator from the
  // seed, the rank and the iteration, and env i of the job's envs [first_env, ...) from
  // StreamSeed(streams_seed, first_env + i) and the iteration.
  void Read(torch::serialize::InputArchive& archive, std::vector<Rng>& env_streams, const char* key,
            uint64_t streams_seed, int first_env);

 private:
  std::shared_ptr<PpoPolicyImpl> policy_;
  RunningNormalizer normalizer_;
  PpoConfig config_;
  uint64_t seed_;
  const Communicator& comm_;
  Ppo ppo_;
  Rollout rollout_;
  int iteration_ = 0;
  long env_steps_ = 0;
};

// The parts of a Gaussian policy's checkpoint that run it: for evaluation and export.
struct TrainedPolicy {
  ActorCritic policy{nullptr};
  RunningNormalizer normalizer{nullptr};
  int iteration = 0;
  long env_steps = 0;
};

// The parts of a checkpoint that run a policy (evaluation, export): its weights, normaliser and
// counters. The caller names the checkpoint in errors.
void ReadPolicyParts(torch::serialize::InputArchive& archive, torch::nn::Module& policy, torch::nn::Module& normalizer,
                     int& iteration, long& env_steps);

}  // namespace flsd
