#include "skills/learning/tasks/skill_discovery_task.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/check.h"
#include "robot/observation.h"
#include "skills/learning/runners/checkpoint_io.h"
#include "skills/learning/tasks/smoothness.h"

namespace flsd {
namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The policy normaliser covers o^m and the previous action; the one-hot skill stays as it is.
constexpr int kNormalizedObs = kMotionObsSize + kActionSize;
constexpr uint64_t kSkillStream = 1000003;  // the skill draws' seed offset from the run's seed

int DiscriminatorInputs(Method method, const TrainConfig& config) {
  return config.discriminator.skill_frame_size() +
         (method == Method::kFlsd ? 2 * config.pae.latent_channels : kMotionObsSize);
}

// The mirror image of q: (x, y) or (x, y, heading turned).
mirror::SignedPermutation MirroredSkillFrame(const DiscriminatorConfig& config) {
  return config.heading ? mirror::PlanarPose() : mirror::PlanarPosition();
}

// Checks the config, seeds libtorch's generator and passes the config on: used to initialise the
// first member, so that the seed is set before any network draws its initial weights.
const TrainConfig& CheckedAndSeeded(const TrainConfig& config) {
  ValidateTrainConfig(config, "training config");
  torch::manual_seed(config.seed);
  return config;
}

}  // namespace

torch::Tensor IntrinsicReward(const torch::Tensor& log_probs, const torch::Tensor& skills) {
  return log_probs.gather(1, skills.unsqueeze(1)).squeeze(1) + std::log(static_cast<double>(log_probs.size(1)));
}

SkillDiscoveryTask::SkillDiscoveryTask(const TrainConfig& config, const Communicator& comm)
    : config_(CheckedAndSeeded(config)),
      comm_(comm),
      method_(ParseMethod(config.method)),
      num_envs_(LocalEnvCount(config.num_envs, comm)),
      steps_(config.steps_per_env),
      policy_obs_size_(PolicyObservationSize(config.num_skills)),
      critic_obs_size_(PolicyObservationSize(config.num_skills) + config.discriminator.skill_frame_size()),
      vec_(config.env, num_envs_, config.seed, ResolveThreadCount(config.num_threads), comm.rank() * num_envs_),
      streams_(num_envs_, steps_, config.window),
      policy_(policy_obs_size_, critic_obs_size_, kActionSize, config.policy),
      pae_(kMotionObsSize, config.window, 1.0 / a1::kControlDt, config.pae),
      discriminator_(DiscriminatorInputs(method_, config), config.num_skills, config.discriminator),
      pairing_(SkillPairingOf(config.num_skills, config.symmetry)),
      travel_targets_(config.travel.enabled() ? ParseSkillTravelTargets(config.travel, config.num_skills)
                                              : SkillTravelTargets()),
      constraint_terminations_(config.constraint_terminations),
      pae_optimizer_(pae_->parameters(),
                     torch::optim::AdamWOptions(config.pae.learning_rate).weight_decay(config.pae.weight_decay)),
      discriminator_optimizer_(discriminator_->parameters(),
                               torch::optim::AdamOptions(config.discriminator.learning_rate)) {
  const int n = num_envs_, t = steps_;
  skill_.resize(n);
  previous_action_.assign(n * kActionSize, 0.0f);
  previous_joint_velocity_.assign(n * a1::kNumJoints, 0.0);
  episode_length_.assign(n, 0);
  steps_to_switch_.assign(n, 0);
  skill_origin_.assign(n, {0.0, 0.0, 0.0});
  heading_turned_.assign(n, 0.0);
  last_yaw_.assign(n, 0.0);
  critic_position_.assign(config.discriminator.skill_frame_size() * n, 0.0f);
  steps_since_switch_.assign(n, config.skill_switch.reward_mask_steps);
  ended_.assign(n, 0);
  ended_length_sum_.assign(n, 0);
  ended_falls_.assign(n, 0);
  for (int i = 0; i < n; ++i) {
    skill_rng_.emplace_back(StreamSeed(config.seed + kSkillStream, comm.rank() * n + i));
    DrawSkill(i);
    if (encodes_windows()) streams_.Restart(i, vec_.motion_obs() + i * kMotionObsSize);
    last_yaw_[i] = vec_.env(i).state().Yaw();
    const a1::JointArray<double>& qd = vec_.env(i).state().joint_velocity;
    std::copy(qd.begin(), qd.end(), &previous_joint_velocity_[i * a1::kNumJoints]);
  }
  const auto f = torch::kFloat32;
  switching_ = torch::zeros({t, n}, f);
  if (config.env.constraints.enabled) violations_ = torch::zeros({t, n, kNumConstraints}, f);
  next_motion_ = torch::zeros({t, n, kMotionObsSize}, f);
  next_position_ = torch::zeros({t, n, config.discriminator.skill_frame_size()}, f);
  skills_ = torch::zeros({t, n}, torch::kLong);
  penalties_ = torch::zeros({t, n}, f);
  if (config.travel.enabled()) travel_ = torch::zeros({t, n}, f);
}

RolloutShape SkillDiscoveryTask::shape() const {
  return {steps_, num_envs_, policy_obs_size_, critic_obs_size_, kActionSize, 2 * kActionSize};
}

int SkillDiscoveryTask::normalized_obs() const { return kNormalizedObs; }

uint64_t SkillDiscoveryTask::env_streams_seed() const { return config_.seed + kSkillStream; }

void SkillDiscoveryTask::DrawSkill(int i) {
  Rng& rng = skill_rng_[i];
  skill_[i] = std::uniform_int_distribution<int>(0, config_.num_skills - 1)(rng);
  const SkillSwitchConfig& s = config_.skill_switch;
  if (s.enabled()) {
    const double seconds = Uniform(rng, s.interval_s.lo, s.interval_s.hi);
    steps_to_switch_[i] = std::max(1, static_cast<int>(std::lround(seconds / a1::kControlDt)));
  }
}

void SkillDiscoveryTask::Observe(torch::Tensor& raw) {
  float* out = raw.data_ptr<float>();
  for (int i = 0; i < num_envs_; ++i) {
    BuildPolicyObservation(vec_.motion_obs() + i * kMotionObsSize, &previous_action_[i * kActionSize], skill_[i],
                           config_.num_skills, out + i * policy_obs_size_);
  }
}

void SkillDiscoveryTask::SkillFramePosition(int i, const float* world, float* out) const {
  const auto& [x0, y0, yaw0] = skill_origin_[i];
  const double dx = world[0] - x0, dy = world[1] - y0, c = std::cos(yaw0), s = std::sin(yaw0);
  out[0] = static_cast<float>(c * dx + s * dy);
  out[1] = static_cast<float>(-s * dx + c * dy);
  if (config_.discriminator.heading) out[2] = static_cast<float>(heading_turned_[i]);
}

void SkillDiscoveryTask::TurnHeading(int i, double yaw) {
  heading_turned_[i] += std::remainder(yaw - last_yaw_[i], 2.0 * M_PI);
  last_yaw_[i] = yaw;
}

double SkillDiscoveryTask::TravelPay(int i) const {
  const std::optional<TravelTarget>& target = travel_targets_[skill_[i]];
  if (!target) return 0.0;
  const RobotState& s = vec_.stepped_state(i);
  const Eigen::Vector3d v = s.base_orientation * s.base_linear_velocity;  // world frame
  const double yaw0 = skill_origin_[i][2], c = std::cos(yaw0), sn = std::sin(yaw0);
  const double yaw_rate = (s.base_orientation * s.base_angular_velocity).z();
  const double pay = TravelReward(*target, {c * v.x() + sn * v.y(), -sn * v.x() + c * v.y(), yaw_rate}, config_.travel);
  if (config_.travel.slip_tolerance <= 0.0) return pay;
  return pay * TravelSlipShare(vec_.violations()[i * kNumConstraints + static_cast<int>(Constraint::kFootSlip)],
                               config_.travel);
}

bool SkillDiscoveryTask::HeldUpright(int i) const {
  if (!config_.travel.upright) return false;
  const std::optional<TravelTarget>& target = travel_targets_[skill_[i]];
  return target && (!target->still || config_.travel.upright_still);
}

// The critic's o^p and q, q in the current skill's frame (SkillFramePosition).
torch::Tensor SkillDiscoveryTask::CriticObservations(const torch::Tensor& obs) {
  const int size = config_.discriminator.skill_frame_size();
  for (int i = 0; i < num_envs_; ++i) SkillFramePosition(i, vec_.position() + 3 * i, &critic_position_[size * i]);
  const torch::Tensor q = torch::from_blob(critic_position_.data(), {num_envs_, size}) * config_.critic_position_scale;
  return torch::cat({obs, q}, 1);
}

void SkillDiscoveryTask::BeginRollout() {
  stats_ = SkillDiscoveryStats{};
  if (encodes_windows()) streams_.BeginRollout();
  std::fill(ended_.begin(), ended_.end(), 0);
  std::fill(ended_length_sum_.begin(), ended_length_sum_.end(), 0);
  std::fill(ended_falls_.begin(), ended_falls_.end(), 0);
}

void SkillDiscoveryTask::Step(int t, const torch::Tensor& actions, Rollout& rollout) {
  float* switching = switching_[t].data_ptr<float>();
  for (int i = 0; i < num_envs_; ++i) switching[i] = steps_since_switch_[i] < config_.skill_switch.reward_mask_steps;
  std::copy(skill_.begin(), skill_.end(), skills_[t].data_ptr<int64_t>());

  Clock::time_point start = Clock::now();
  vec_.Step(actions.data_ptr<float>());
  stats_.seconds_physics += Since(start);

  start = Clock::now();
  AfterStep(t, actions.data_ptr<float>(), rollout);
  stats_.seconds_bookkeeping += Since(start);
}

void SkillDiscoveryTask::AfterStep(int t, const float* actions, Rollout& rollout) {
  const int n = num_envs_;
  const int q_size = config_.discriminator.skill_frame_size();
  const bool windows = encodes_windows();
  float* next_motion = next_motion_[t].data_ptr<float>();
  float* next_position = next_position_[t].data_ptr<float>();
  float* dones = rollout.dones[t].data_ptr<float>();
  float* timeouts = rollout.timeouts[t].data_ptr<float>();
  float* penalties = penalties_[t].data_ptr<float>();
  float* travel = travel_.defined() ? travel_[t].data_ptr<float>() : nullptr;
  float* violations = violations_.defined() ? violations_[t].data_ptr<float>() : nullptr;
  const RegularizationConfig& regularization = config_.regularization;
  vec_.pool().ParallelFor(n, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      const Termination ending = vec_.termination()[i];
      const bool done = ending != Termination::kNone;
      // o^m_{t+1} and q_{t+1}: the final state of an episode that just ended, not the reset one.
      const float* next = (done ? vec_.terminal_motion_obs() : vec_.motion_obs()) + i * kMotionObsSize;
      const float* position = (done ? vec_.terminal_position() : vec_.position()) + i * 3;
      if (windows) streams_.Push(i, t, next);
      std::copy(next, next + kMotionObsSize, next_motion + i * kMotionObsSize);
      TurnHeading(i, vec_.stepped_state(i).Yaw());
      if (travel != nullptr) travel[i] = static_cast<float>(TravelPay(i));  // the skill that took the step
      SkillFramePosition(i, position, next_position + q_size * i);
      dones[i] = done ? 1.0f : 0.0f;
      if (violations != nullptr) {
        const float* v = vec_.violations() + i * kNumConstraints;
        float* out = violations + i * kNumConstraints;
        std::copy(v, v + kNumConstraints, out);
        if (HeldUpright(i)) {
          float& low = out[static_cast<int>(Constraint::kLowBaseMoving)];
          low = std::max(low, static_cast<float>(BaseHeightShortfall(vec_.stepped_state(i), config_.env.constraints)));
        }
      }
      timeouts[i] = ending == Termination::kTimeOut ? 1.0f : 0.0f;
      ++episode_length_[i];
      float* previous = &previous_action_[i * kActionSize];
      double* previous_qd = &previous_joint_velocity_[i * a1::kNumJoints];
      if (regularization.enabled()) {
        const double action_rate = ActionRate(actions + i * kActionSize, previous);
        const double dof_acc = JointAcceleration(vec_.stepped_state(i).joint_velocity.data(), previous_qd);
        penalties[i] = static_cast<float>(
            (regularization.action_rate * action_rate + regularization.dof_acc * dof_acc) * a1::kControlDt);
      }
      const a1::JointArray<double>& qd_now = vec_.env(i).state().joint_velocity;  // after any reset
      std::copy(qd_now.begin(), qd_now.end(), previous_qd);
      if (done) {
        ++ended_[i];
        ended_length_sum_[i] += episode_length_[i];
        ended_falls_[i] += IsFailure(ending);
        episode_length_[i] = 0;
        // A new episode: a new skill drawn from the uniform prior, a fresh motion history.
        DrawSkill(i);
        steps_since_switch_[i] = config_.skill_switch.reward_mask_steps;
        skill_origin_[i] = {0.0, 0.0, 0.0};  // every episode starts at the origin facing +x
        heading_turned_[i] = 0.0;
        last_yaw_[i] = vec_.env(i).state().Yaw();
        std::fill(previous, previous + kActionSize, 0.0f);
        if (windows) streams_.Restart(i, vec_.motion_obs() + i * kMotionObsSize);
      } else {
        std::copy(actions + i * kActionSize, actions + (i + 1) * kActionSize, previous);
        ++steps_since_switch_[i];
        // Within the episode, the next skill takes over from this one's motion.
        if (config_.skill_switch.enabled() && --steps_to_switch_[i] <= 0) {
          const int before = skill_[i];
          DrawSkill(i);
          if (skill_[i] != before) {
            // The new skill's q starts from where, and the way, the robot now is.
            const RobotState& s = vec_.env(i).state();
            skill_origin_[i] = {s.base_position.x(), s.base_position.y(), s.Yaw()};
            heading_turned_[i] = 0.0;
            steps_since_switch_[i] = 0;
          }
        }
      }
    }
  });
}

void SkillDiscoveryTask::FinishRollout(Rollout& rollout, int iteration) {
  torch::NoGradGuard no_grad;
  double ended[3] = {0.0, 0.0, 0.0};  // episodes, their lengths, falls: over all ranks
  for (int i = 0; i < num_envs_; ++i) {
    ended[0] += ended_[i];
    ended[1] += ended_length_sum_[i];
    ended[2] += ended_falls_[i];
  }
  comm_.Sum(ended, 3);
  stats_.episodes_ended = static_cast<int>(ended[0]);
  stats_.mean_episode_length = ended[0] > 0 ? ended[1] / ended[0] : 0.0;
  stats_.fall_fraction = ended[0] > 0 ? ended[2] / ended[0] : 0.0;

  const int64_t count = static_cast<int64_t>(steps_) * num_envs_;
  const torch::Tensor positions = next_position_.view({count, config_.discriminator.skill_frame_size()});
  // Eq. 13: FLSD's o^d = [q, P], P the phase manifold of the window ending at t + 1; DIAYN's
  // o^d = [q, o^m].
  if (encodes_windows()) windows_ = streams_.Frames();
  const torch::Tensor features = encodes_windows() ? pae_->ManifoldAlong(windows_.frames, windows_.ends)
                                                   : next_motion_.view({count, kMotionObsSize});
  const torch::Tensor observations = torch::cat({positions, features}, 1);
  const torch::Tensor skills = skills_.view({count});
  const torch::Tensor log_probs = discriminator_->LogProbs(observations);
  torch::Tensor reward = IntrinsicReward(log_probs, skills);
  // Means over all ranks (each holds as many transitions).
  double means[4] = {reward.mean().item<double>(),
                     (log_probs.argmax(1) == skills).to(torch::kFloat32).mean().item<double>(),
                     penalties_.mean().item<double>(), travel_.defined() ? travel_.mean().item<double>() : 0.0};
  comm_.Sum(means, 4);
  stats_.intrinsic_reward = means[0] / comm_.size();
  stats_.discriminator_accuracy = means[1] / comm_.size();
  stats_.regularization = means[2] / comm_.size();
  stats_.travel_reward = means[3] / comm_.size();
  if (travel_.defined()) reward = reward + travel_.view({count});
  // As legged_gym clips its total: penalties included, so that no step pays less than ending.
  const torch::Tensor total = config_.reward_scale * reward + penalties_.view({count});
  torch::Tensor rewards = (config_.only_positive_rewards ? total.clamp_min(0.0) : total).view({steps_, num_envs_});
  // Just after a skill switch the window mixes two skills' motions: no reward for it.
  rewards = rewards * (1.0 - switching_);
  if (violations_.defined()) {
    // CaT: a violation ends the episode with its probability, which scales the step's reward and
    // what the step bootstraps from its successor.
    const torch::Tensor p = constraint_terminations_.Probabilities(violations_, iteration, comm_, stats_.constraints);
    rewards = rewards * (1.0 - p);
    rollout.dones.copy_(torch::max(rollout.dones, p));
  }
  rollout.rewards.copy_(rewards);
  DiscriminatorSamples(observations, positions);
}

torch::Tensor SkillDiscoveryTask::MirroredFeatures(int64_t count) {
  const mirror::SignedPermutation motion = mirror::MotionObservation();
  if (encodes_windows()) return pae_->ManifoldAlong(MirrorAlong(motion, windows_.frames, 0), windows_.ends);
  return MirrorAlong(motion, next_motion_.view({count, kMotionObsSize}), 1);
}

void SkillDiscoveryTask::DiscriminatorSamples(const torch::Tensor& observations, const torch::Tensor& positions) {
  const int64_t count = observations.size(0);
  const torch::Tensor skills = skills_.view({count});
  const torch::Tensor kept = (switching_.view({count}) == 0).nonzero().squeeze(1);
  discriminator_obs_ = observations.index_select(0, kept);
  discriminator_labels_ = skills.index_select(0, kept);
  if (!config_.symmetry.enabled) return;
  // The mirror image of skill k's sample is a sample of k's pair.
  const torch::Tensor mirrored =
      torch::cat({MirrorAlong(MirroredSkillFrame(config_.discriminator), positions, 1), MirroredFeatures(count)}, 1);
  discriminator_obs_ = torch::cat({discriminator_obs_, mirrored.index_select(0, kept)}, 0);
  discriminator_labels_ =
      torch::cat({discriminator_labels_, PairIndex(pairing_).index_select(0, skills).index_select(0, kept)}, 0);
}

MirroredSamples SkillDiscoveryTask::Mirror(const torch::Tensor& raw_obs, const Rollout& rollout,
                                           const RunningNormalizer& normalizer) const {
  torch::NoGradGuard no_grad;
  const int64_t count = raw_obs.size(0);
  MirroredSamples m;
  m.obs = NormalizeLeadingColumns(normalizer, MirrorAlong(mirror::PolicyObservation(pairing_), raw_obs, 1));
  const torch::Tensor position = rollout.critic_obs.view({count, critic_obs_size_}).slice(1, policy_obs_size_);
  m.critic_obs = torch::cat({m.obs, MirrorAlong(MirroredSkillFrame(config_.discriminator), position, 1)}, 1);
  m.actions = MirrorAlong(mirror::Joints(), rollout.actions.view({count, kActionSize}), 1);
  return m;
}

double SkillDiscoveryTask::UpdatePae() {
  const PaeConfig& c = config_.pae;
  const int64_t count = static_cast<int64_t>(steps_) * num_envs_;
  const int64_t sampled = std::max<int64_t>(1, std::llround(c.sample_fraction * count));
  const torch::Tensor chosen = torch::randperm(count, torch::kLong).slice(0, 0, sampled);
  const mirror::SignedPermutation motion = mirror::MotionObservation();
  return TrainEpochs(pae_optimizer_, comm_, chosen, c.epochs, c.minibatch_size, [&](const torch::Tensor& idx) {
    torch::Tensor x = WindowsAlong(windows_.frames, windows_.ends.index_select(0, idx), config_.window);
    // With symmetry, half of the windows are mirror images, so that the manifold of a mirrored
    // window (the discriminator's mirrored samples) is in the PAE's training distribution.
    if (config_.symmetry.enabled) {
      const int64_t half = x.size(0) / 2;
      x = torch::cat({x.slice(0, 0, half), MirrorAlong(motion, x.slice(0, half), 1)}, 0);
    }
    return pae_->Loss(x, pae_->Forward(x));  // Eq. 3
  });
}

double SkillDiscoveryTask::UpdateDiscriminator() {
  const DiscriminatorConfig& c = config_.discriminator;
  const torch::Tensor all = torch::arange(discriminator_obs_.size(0), torch::kLong);
  return TrainEpochs(discriminator_optimizer_, comm_, all, c.epochs, c.minibatch_size, [&](const torch::Tensor& idx) {
    // Eq. 12 on (o^d, k) pairs of this rollout.
    return DiscriminatorLoss(discriminator_->LogProbs(Blurred(discriminator_obs_.index_select(0, idx), c)),
                             discriminator_labels_.index_select(0, idx));
  });
}

bool SkillDiscoveryTask::UpdateAuxiliaries() {
  Clock::time_point phase = Clock::now();
  if (encodes_windows()) stats_.pae_loss = UpdatePae();
  stats_.seconds_pae = Since(phase);

  phase = Clock::now();
  stats_.discriminator_loss = UpdateDiscriminator();
  stats_.seconds_discriminator = Since(phase);

  stats_.action_std = policy_->Std().mean().item<double>();
  const bool finite = std::isfinite(stats_.pae_loss) && std::isfinite(stats_.discriminator_loss);
  if (!finite) {
    spdlog::error("not finite:{}{}", std::isfinite(stats_.pae_loss) ? "" : " the PAE's loss",
                  std::isfinite(stats_.discriminator_loss) ? "" : " the discriminator's loss");
  }
  return finite;
}

// ---- checkpoints ----

void SkillDiscoveryTask::Save(torch::serialize::OutputArchive& archive) const {
  WriteModule(archive, "pae", *pae_);
  WriteModule(archive, "discriminator", *discriminator_);
  WriteOptimizer(archive, "pae_optimizer", pae_optimizer_);
  WriteOptimizer(archive, "discriminator_optimizer", discriminator_optimizer_);
  archive.write("config", c10::IValue(ToYamlString(config_)));
  archive.write("constraint_scales", c10::IValue(constraint_terminations_.State()));
}

void SkillDiscoveryTask::Load(torch::serialize::InputArchive& archive, const std::string& path) {
  ReadModule(archive, "pae", *pae_);
  ReadModule(archive, "discriminator", *discriminator_);
  ReadOptimizer(archive, "pae_optimizer", pae_optimizer_);
  ReadOptimizer(archive, "discriminator_optimizer", discriminator_optimizer_);
  c10::IValue scales{std::string()};  // checkpoints from before constraints as terminations
  if (archive.try_read("constraint_scales", scales) && !scales.toStringRef().empty()) {
    constraint_terminations_.Restore(scales.toStringRef(), path);
  }
}

TrainedPolicy LoadTrainedPolicy(const TrainConfig& config, const std::string& checkpoint) {
  torch::serialize::InputArchive archive = OpenCheckpoint(checkpoint);
  TrainedPolicy out;
  const int obs = PolicyObservationSize(config.num_skills);
  out.policy = ActorCritic(obs, obs + config.discriminator.skill_frame_size(), kActionSize, config.policy);
  out.normalizer = RunningNormalizer(kNormalizedObs);
  try {
    ReadPolicyParts(archive, *out.policy, *out.normalizer, out.iteration, out.env_steps);
  } catch (const c10::Error& e) {
    MismatchedCheckpoint(checkpoint, e);
  } catch (const InputError& e) {
    throw InputError(checkpoint + ": does not fit this training config: " + e.what());
  }
  return out;
}

// ---- progress ----

ProgressRecord SkillDiscoveryTask::Progress(const RunnerStats& runner) const { return SkillProgress(runner, stats_); }

ProgressRecord SkillProgress(const RunnerStats& r, const SkillDiscoveryStats& s) {
  ProgressRecord record;
  record.Add("iteration", long{r.iteration})
      .Add("env_steps", r.env_steps)
      .Add("steps_per_s", r.steps_per_s, "%.1f")
      .Add("episodes_ended", long{s.episodes_ended})
      .Add("mean_episode_length", s.mean_episode_length, "%.2f")
      .Add("fall_fraction", s.fall_fraction, "%.4f")
      .Add("discriminator_accuracy", s.discriminator_accuracy, "%.5f")
      .Add("intrinsic_reward", s.intrinsic_reward, "%.5f")
      .Add("discriminator_loss", s.discriminator_loss, "%.5f")
      .Add("pae_loss", s.pae_loss, "%.6f")
      .Add("surrogate_loss", r.ppo.surrogate_loss, "%.6f")
      .Add("value_loss", r.ppo.value_loss, "%.6f")
      .Add("entropy", r.ppo.entropy, "%.5f")
      .Add("kl", r.ppo.kl, "%.6f")
      .Add("learning_rate", r.ppo.learning_rate, "%.3g")
      .Add("action_std", s.action_std, "%.5f")
      .Add("seconds_physics", s.seconds_physics, "%.4f")
      .Add("seconds_policy", r.seconds_policy, "%.4f")
      .Add("seconds_bookkeeping", s.seconds_bookkeeping, "%.4f")
      .Add("seconds_reward", r.seconds_finish, "%.4f")
      .Add("seconds_ppo", r.seconds_ppo, "%.4f")
      .Add("seconds_pae", s.seconds_pae, "%.4f")
      .Add("seconds_discriminator", s.seconds_discriminator, "%.4f")
      .Add("seconds_total", r.seconds_total, "%.4f")
      .Add("regularization", s.regularization, "%.6f")
      .Add("termination_probability", s.constraints.mean_probability, "%.5f");
  for (size_t c = 0; c < kConstraintNames.size(); ++c) {
    const std::string column = std::string("violation_") + kConstraintNames[c];
    record.Add(column.c_str(), s.constraints.violation_rate[c], "%.5f");
  }
  record.Add("travel_reward", s.travel_reward, "%.5f");  // last: rows of runs from before it stay aligned
  return record;
}

std::string SkillDiscoveryTask::ProgressLine(const RunnerStats& r, int total_iterations, double eta_seconds) const {
  const SkillDiscoveryStats& s = stats_;
  char line[512];
  std::snprintf(line, sizeof(line),
                "it %d/%d | %.0f steps/s | ETA %s | ep len %.0f (falls %.0f%%) | disc acc %.3f "
                "(chance %.3f) | r_int %.3f | penalty %.4f | pae %.4f | lr %.1e | std %.3f",
                r.iteration, total_iterations, r.steps_per_s, Duration(eta_seconds).c_str(), s.mean_episode_length,
                100.0 * s.fall_fraction, s.discriminator_accuracy, 1.0 / config_.num_skills, s.intrinsic_reward,
                s.regularization, s.pae_loss, r.ppo.learning_rate, s.action_std);
  return line;
}

}  // namespace flsd
