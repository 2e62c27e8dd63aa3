#pragma once
// Algorithm 1 of the paper as a task for the on-policy runner: one skill-conditioned policy earns
// the intrinsic reward log q(k | o^d) - log p(k), while the PAE (FLSD only) and the discriminator
// learn from the same rollouts. The task owns the VecEnv, the skill schedule, the skill frame,
// the motion windows, the constraint terminations and the mirror pairing of skills.

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/rng.h"
#include "sim/vec_env.h"
#include "skills/learning/algorithms/constraint_terminations.h"
#include "skills/learning/algorithms/symmetry.h"
#include "skills/learning/algorithms/train_epochs.h"
#include "skills/learning/networks/actor_critic.h"
#include "skills/learning/networks/discriminator.h"
#include "skills/learning/networks/motion_streams.h"
#include "skills/learning/networks/normalizer.h"
#include "skills/learning/networks/pae.h"
#include "skills/learning/runners/policy_learner.h"
#include "skills/learning/runners/rollout_task.h"
#include "skills/learning/runners/train_config.h"

namespace flsd {

// Eq. 11: log q(k | o^d) - log p(k) with uniform p(k) = 1 / N_k, for skills [B] (int64).
torch::Tensor IntrinsicReward(const torch::Tensor& log_probs, const torch::Tensor& skills);

// The task's figures of one iteration, over every rank.
struct SkillDiscoveryStats {
  int episodes_ended = 0;
  double mean_episode_length = 0.0;   // control steps, of the episodes that ended
  double fall_fraction = 0.0;         // of the episodes that ended, the share that fell
  double discriminator_accuracy = 0.0;
  double intrinsic_reward = 0.0;      // mean of Eq. 11 before any clipping
  double regularization = 0.0;        // mean smoothness penalty per step (dt-scaled, <= 0)
  double travel_reward = 0.0;         // mean pay per step for travelling the skills' ways (TravelConfig)
  ConstraintStats constraints;        // with constraints as terminations
  double discriminator_loss = 0.0;
  double pae_loss = 0.0;
  double action_std = 0.0;
  // Wall seconds: simulation, windows and bookkeeping after each step, the PAE's and the
  // discriminator's updates.
  double seconds_physics = 0.0, seconds_bookkeeping = 0.0, seconds_pae = 0.0, seconds_discriminator = 0.0;
};

// A skill-discovery run's progress.csv columns.
ProgressRecord SkillProgress(const RunnerStats& runner, const SkillDiscoveryStats& task);

// Reads the policy and normaliser of a checkpoint written by a run with `config`.
TrainedPolicy LoadTrainedPolicy(const TrainConfig& config, const std::string& checkpoint);

// With several ranks in `comm`, config.num_envs is the job's: this rank steps its equal share.
class SkillDiscoveryTask : public RolloutTask {
 public:
  // Checks the config and seeds libtorch's generator before any network draws its weights.
  explicit SkillDiscoveryTask(const TrainConfig& config, const Communicator& comm = Communicator::Self());
  SkillDiscoveryTask(const SkillDiscoveryTask&) = delete;
  SkillDiscoveryTask& operator=(const SkillDiscoveryTask&) = delete;

  std::shared_ptr<PpoPolicyImpl> policy() const override { return policy_.ptr(); }
  RolloutShape shape() const override;
  int normalized_obs() const override;
  bool mirrored() const override { return config_.symmetry.enabled; }

  void BeginRollout() override;
  void Observe(torch::Tensor& raw) override;
  torch::Tensor CriticObservations(const torch::Tensor& obs) override;
  void Step(int t, const torch::Tensor& actions, Rollout& rollout) override;
  void FinishRollout(Rollout& rollout, int iteration) override;
  MirroredSamples Mirror(const torch::Tensor& raw_obs, const Rollout& rollout,
                         const RunningNormalizer& normalizer) const override;
  bool UpdateAuxiliaries() override;

  std::vector<Rng>& env_streams() override { return skill_rng_; }
  const char* env_streams_key() const override { return "skill_rng"; }
  uint64_t env_streams_seed() const override;
  void Save(torch::serialize::OutputArchive& archive) const override;
  void Load(torch::serialize::InputArchive& archive, const std::string& path) override;

  ProgressRecord Progress(const RunnerStats& runner) const override;
  std::string ProgressLine(const RunnerStats& runner, int total_iterations, double eta_seconds) const override;

  const TrainConfig& config() const { return config_; }
  Method method() const { return method_; }
  const SkillDiscoveryStats& stats() const { return stats_; }
  ActorCritic actor_critic() const { return policy_; }
  PeriodicAutoencoder pae() const { return pae_; }
  Discriminator discriminator() const { return discriminator_; }
  VecEnv& vec_env() { return vec_; }
  // The last rollout's motion streams (FLSD) and the discriminator's samples, for the bench's count
  // of the learning arithmetic.
  const MotionStreamFrames& motion_windows() const { return windows_; }
  int64_t discriminator_samples() const { return discriminator_obs_.size(0); }

 private:
  // q of env i at world position `world` (3 floats) in the frame the current skill started in:
  // its position and heading when it took over (the origin and +x for an episode's first); with
  // discriminator.heading, then the heading turned since (TurnHeading).
  void SkillFramePosition(int i, const float* world, float* out) const;
  // Adds env i's turn from its last yaw to `yaw` (the shorter way round) to the heading turned.
  void TurnHeading(int i, double yaw);
  // Whether env i's skill is held to the base height at any speed (TravelConfig::upright).
  bool HeldUpright(int i) const;
  // Env i's pay for its last step's travel the way its skill goes (TravelReward, in the skill's
  // frame, less for a skating step with travel.slip_tolerance); 0 for a skill without a direction.
  double TravelPay(int i) const;
  // Records the step's transition of every env (windows, q, ends, penalties) and moves each env's
  // episode and skill schedule on.
  void AfterStep(int t, const float* actions, Rollout& rollout);
  void DrawSkill(int env);
  bool encodes_windows() const { return method_ == Method::kFlsd; }
  // The discriminator's training samples and labels: this rollout's, but for the steps just after
  // a skill switch, and with symmetry their mirror images too.
  void DiscriminatorSamples(const torch::Tensor& features, const torch::Tensor& positions);
  torch::Tensor MirroredFeatures(int64_t count);
  double UpdatePae();
  double UpdateDiscriminator();

  TrainConfig config_;
  const Communicator& comm_;
  Method method_;
  int num_envs_, steps_;
  int policy_obs_size_, critic_obs_size_;
  VecEnv vec_;
  MotionStreams streams_;  // o^m of every env, read as the PAE's windows (FLSD)

  ActorCritic policy_{nullptr};
  PeriodicAutoencoder pae_{nullptr};
  Discriminator discriminator_{nullptr};
  mirror::SkillPairing pairing_;
  SkillTravelTargets travel_targets_;  // with travel.weight > 0
  ConstraintTerminations constraint_terminations_;
  torch::optim::AdamW pae_optimizer_;
  torch::optim::Adam discriminator_optimizer_;
  SkillDiscoveryStats stats_;

  // Per env.
  std::vector<int> skill_;
  std::vector<Rng> skill_rng_;
  std::vector<float> previous_action_;
  std::vector<double> previous_joint_velocity_;  // per env x 12, for the dof_acc penalty
  std::vector<int> episode_length_;
  std::vector<int> steps_to_switch_, steps_since_switch_;  // skill switching within an episode
  std::vector<std::array<double, 3>> skill_origin_;  // per env: x, y (m) and yaw (rad) at the switch
  std::vector<double> heading_turned_, last_yaw_;    // per env: rad turned since the switch, last yaw
  std::vector<float> critic_position_;               // per env: q in the skill's frame
  std::vector<int> ended_, ended_length_sum_, ended_falls_;

  // The rollout's own parts, [T, N, ...].
  torch::Tensor switching_;      // [T, N] 1 within reward_mask_steps of a skill switch
  torch::Tensor violations_;     // [T, N, kNumConstraints] (constraints as terminations)
  MotionStreamFrames windows_;   // o^H_{t+1} as the streams and where each window ends (FLSD)
  torch::Tensor next_motion_;    // [T, N, 33] o^m_{t+1}
  torch::Tensor next_position_;  // [T, N, 2 or 3] q at t+1
  torch::Tensor skills_;         // [T, N] int64
  torch::Tensor penalties_;      // [T, N] smoothness penalties (RegularizationConfig), dt-scaled
  torch::Tensor travel_;         // [T, N] TravelPay (travel.weight > 0)
  torch::Tensor discriminator_obs_;     // [M, o^d], the discriminator's training samples
  torch::Tensor discriminator_labels_;  // [M] int64
};

}  // namespace flsd
