#pragma once
// Algorithm 1 of the paper: PPO trains one skill-conditioned policy on the intrinsic reward
// log q(k | o^d) - log p(k), while the PAE (FLSD only) and the discriminator are trained on the
// same rollouts.

#include <array>
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "core/rng.h"
#include "sim/vec_env.h"
#include "skills/learning/networks/actor_critic.h"
#include "skills/learning/runners/communicator.h"
#include "skills/learning/networks/discriminator.h"
#include "skills/learning/tasks/motion_history.h"
#include "skills/learning/networks/normalizer.h"
#include "skills/learning/networks/pae.h"
#include "skills/learning/runners/policy_learner.h"
#include "skills/learning/runners/train_config.h"

namespace flsd {

// What one iteration did; a row of the run's progress.csv.
struct IterationStats {
  int iteration = 0;
  long env_steps = 0;                 // since the run began
  double steps_per_s = 0.0;           // env steps over the whole iteration's wall time
  int episodes_ended = 0;
  double mean_episode_length = 0.0;   // control steps, of the episodes that ended
  double fall_fraction = 0.0;         // of the episodes that ended, the share that fell
  double discriminator_accuracy = 0.0;
  double intrinsic_reward = 0.0;      // mean of Eq. 11 before any clipping
  double regularization = 0.0;        // mean smoothness penalty per step (dt-scaled, <= 0)
  ConstraintStats constraints;        // with constraints as terminations
  double discriminator_loss = 0.0;
  double pae_loss = 0.0;
  double action_std = 0.0;
  PpoStats ppo;
  bool finite = true;
  // Wall seconds spent in each part of the iteration.
  double seconds_physics = 0.0, seconds_policy = 0.0, seconds_bookkeeping = 0.0,
         seconds_reward = 0.0, seconds_ppo = 0.0, seconds_pae = 0.0, seconds_discriminator = 0.0,
         seconds_total = 0.0;
  Communicator::Tally collectives;  // MPI collectives within the iteration (none in one process)
};

// `epochs` passes over `samples` (row indices) in shuffled minibatches, one optimiser step each
// on loss_of(minibatch). Every rank of `comm` passes over its own samples, as many as the others,
// and the ranks step together on their averaged gradients: `minibatch` is the size of the ranks'
// minibatches together. Returns the mean loss over the ranks, or NaN, without stepping, as soon as
// a loss is not finite on any rank.
double TrainEpochs(torch::optim::Optimizer& optimizer, const Communicator& comm, const torch::Tensor& samples,
                   int epochs, int64_t minibatch, const std::function<torch::Tensor(const torch::Tensor&)>& loss_of);

// The parts of a checkpoint that run the policy: for evaluation and export.
struct TrainedPolicy {
  ActorCritic policy{nullptr};
  RunningNormalizer normalizer{nullptr};
  int iteration = 0;
  long env_steps = 0;
};
// Reads the policy and normaliser of a checkpoint written by a trainer with `config`.
TrainedPolicy LoadTrainedPolicy(const TrainConfig& config, const std::string& checkpoint);

// With several ranks in `comm` (data-parallel training under MPI), config.num_envs is the total:
// each rank steps its equal share of the envs, and the ranks average every gradient and merge the
// normaliser's statistics, so all hold the same parameters. Figures in IterationStats are the
// whole job's.
class Trainer {
 public:
  explicit Trainer(const TrainConfig& config, const Communicator& comm = Communicator::Self());
  Trainer(const Trainer&) = delete;
  Trainer& operator=(const Trainer&) = delete;

  // One iteration of Algorithm 1: collect a rollout, compute rewards, update PPO, PAE and
  // discriminator.
  IterationStats RunIteration();

  // Checkpoints hold the networks, optimisers, normaliser, counters and random states; the file
  // is written atomically. Loading checks that the shapes match this trainer's config.
  // With several ranks, only the leader should save. A checkpoint resumes with any number of
  // ranks; the random streams are restored only in one process resuming a one-process checkpoint
  // (and are otherwise drawn afresh from the seed, the rank and the iteration).
  void SaveCheckpoint(const std::string& path) const;
  void LoadCheckpoint(const std::string& path);

  const TrainConfig& config() const { return config_; }
  Method method() const { return method_; }
  int iteration() const { return learner_.iteration(); }
  long env_steps() const { return learner_.env_steps(); }
  ActorCritic policy() const { return policy_; }
  RunningNormalizer normalizer() const { return learner_.normalizer(); }
  PeriodicAutoencoder pae() const { return pae_; }
  Discriminator discriminator() const { return discriminator_; }
  int policy_obs_size() const { return policy_obs_size_; }
  VecEnv& vec_env() { return vec_; }
  const Communicator& communicator() const { return comm_; }

 private:
  void CollectRollout(IterationStats& stats);
  torch::Tensor PolicyObservations(bool update_normalizer);
  // The critic's o^p and q, q in the current skill's frame (SkillFramePosition).
  torch::Tensor CriticObservations(const torch::Tensor& obs);
  // q of env i at world position `world` (3 floats) in the frame the current skill started in:
  // its position and heading when it took over (the origin and +x for an episode's first); with
  // discriminator.heading, then the heading turned since (TurnHeading).
  void SkillFramePosition(int i, const float* world, float* out) const;
  // Adds env i's turn from its last yaw to `yaw` (the shorter way round) to the heading turned.
  void TurnHeading(int i, double yaw);
  void AfterStep(int t, const float* actions);
  void ComputeRewards(IterationStats& stats);
  void DrawSkill(int env);
  // The discriminator's training samples and labels: this rollout's, but for the steps just after
  // a skill switch, and with symmetry their mirror images too.
  void DiscriminatorSamples(const torch::Tensor& features, const torch::Tensor& positions);
  torch::Tensor Manifold(const torch::Tensor& windows);
  torch::Tensor MirroredFeatures(int64_t count);
  MirroredSamples MirroredRollout() const;
  double UpdatePae();
  double UpdateDiscriminator();

  TrainConfig config_;
  const Communicator& comm_;
  Method method_;
  int num_envs_, steps_;
  int policy_obs_size_, critic_obs_size_;
  VecEnv vec_;

  ActorCritic policy_{nullptr};
  PeriodicAutoencoder pae_{nullptr};
  Discriminator discriminator_{nullptr};
  PolicyLearner learner_;
  Rollout& rollout_;  // the learner's
  mirror::SkillPairing pairing_;
  ConstraintTerminations constraint_terminations_;
  torch::optim::AdamW pae_optimizer_;
  torch::optim::Adam discriminator_optimizer_;

  // Per env.
  std::vector<int> skill_;
  std::vector<Rng> skill_rng_;
  std::vector<float> previous_action_;
  std::vector<double> previous_joint_velocity_;  // per env x 12, for the dof_acc penalty
  std::vector<MotionHistory> history_;
  std::vector<int> episode_length_;
  std::vector<int> steps_to_switch_, steps_since_switch_;  // skill switching within an episode
  std::vector<std::array<double, 3>> skill_origin_;  // per env: x, y (m) and yaw (rad) at the switch
  std::vector<double> heading_turned_, last_yaw_;    // per env: rad turned since the switch, last yaw
  std::vector<float> critic_position_;               // per env: q in the skill's frame
  std::vector<int> ended_, ended_length_sum_, ended_falls_;

  // The rollout's other parts, [T, N, ...].
  torch::Tensor raw_obs_;        // [N, policy_obs_size], this step's unnormalised o^p
  torch::Tensor raw_rollout_obs_;  // [T, N, policy_obs_size] unnormalised o^p (symmetry)
  torch::Tensor switching_;      // [T, N] 1 within reward_mask_steps of a skill switch
  torch::Tensor violations_;     // [T, N, kNumConstraints] (constraints as terminations)
  torch::Tensor windows_;        // [T, N, 33, H] o^H_{t+1} (FLSD)
  torch::Tensor next_motion_;    // [T, N, 33] o^m_{t+1}
  torch::Tensor next_position_;  // [T, N, 2 or 3] q at t+1
  torch::Tensor skills_;         // [T, N] int64
  torch::Tensor penalties_;      // [T, N] smoothness penalties (RegularizationConfig), dt-scaled
  torch::Tensor discriminator_obs_;     // [M, o^d], the discriminator's training samples
  torch::Tensor discriminator_labels_;  // [M] int64
  torch::Tensor last_values_;    // [N]
};

}  // namespace flsd
