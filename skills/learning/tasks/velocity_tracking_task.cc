#include "skills/learning/tasks/velocity_tracking_task.h"

#include <cmath>
#include <cstdio>
#include <functional>

#include "core/check.h"
#include "robot/mirror.h"
#include "robot/observation.h"
#include "skills/learning/algorithms/symmetry.h"
#include "skills/learning/runners/checkpoint_io.h"

namespace flsd {
namespace {

const VelocityTrainConfig& CheckedAndSeeded(const VelocityTrainConfig& config) {
  ValidateVelocityTrainConfig(config, "velocity training config");
  torch::manual_seed(config.seed);
  return config;
}

std::optional<SkillLibrary> LoadSelectorLibrary(const VelocityTrainConfig& config) {
  if (ParseVelocityMethod(config.method) != VelocityMethod::kSelector) return std::nullopt;
  return SkillLibrary::Load(config.library);
}

}  // namespace

VelocityMethod ParseVelocityMethod(const std::string& name) {
  if (name == "selector") return VelocityMethod::kSelector;
  if (name == "scratch") return VelocityMethod::kScratch;
  throw InputError("method: expected 'selector' or 'scratch', got '" + name + "'");
}

SelectorNetwork SelectorShape(const VelocityTrainConfig& config) {
  SelectorNetwork shape;
  shape.decision_interval = config.decision_interval;
  shape.nearest_prior_temperature = config.nearest_prior_temperature;
  shape.time_sharing_prior = config.time_sharing_prior;
  shape.memory_window_steps =
      config.semi_mdp.enabled() ? std::max(1, static_cast<int>(std::lround(config.semi_mdp.window_s / a1::kControlDt))) : 0;
  return shape;
}

int NormalizedVelocityObsSize(const VelocityTrainConfig& config) {
  return ParseVelocityMethod(config.method) == VelocityMethod::kSelector ? SelectorShape(config).normalized_inputs()
                                                                         : kTaskObsSize + kActionSize;
}

int VelocityPolicyObsSize(const VelocityTrainConfig& config, int num_skills) {
  return ParseVelocityMethod(config.method) == VelocityMethod::kSelector
             ? SelectorShape(config).inputs(num_skills) + num_skills
             : kTaskObsSize + kActionSize;
}

PpoConfig VelocityPpoConfig(const VelocityTrainConfig& config) {
  PpoConfig ppo = config.ppo;
  if (config.discount_per_second > 0.0) {
    ppo.gamma = std::pow(config.discount_per_second, config.decision_interval * a1::kControlDt);
  }
  return ppo;
}

void ValidateVelocityTrainConfig(const VelocityTrainConfig& config, const std::string& where) {
  try {
    const VelocityMethod method = ParseVelocityMethod(config.method);
    if (method == VelocityMethod::kSelector && config.library.empty()) {
      throw InputError("library: the selector needs a skill library to choose from (models/*.safetensors)");
    }
    if (method == VelocityMethod::kScratch && (config.nearest_prior() || config.time_sharing_prior > 0.0)) {
      throw InputError("nearest_prior_temperature and time_sharing_prior: a prior over skills needs method 'selector'; "
                       "expected 0");
    }
    if (config.nearest_prior() && config.time_sharing_prior > 0.0) {
      throw InputError("time_sharing_prior: a selector has one prior, but nearest_prior_temperature is set too");
    }
    if (config.mirror && (config.time_sharing_prior > 0.0 || config.semi_mdp.enabled())) {
      throw InputError("mirror: the time-sharing prior and the semi-MDP memory are not mirrored; expected false");
    }
    if (config.semi_mdp.enabled() && config.reward_streams) {
      throw InputError("reward_streams: a semi-MDP selector has one reward; expected false");
    }
    if (method == VelocityMethod::kScratch && config.decision_interval != 1) {
      throw InputError("decision_interval: the scratch policy acts every control step; expected 1, got " +
                       std::to_string(config.decision_interval));
    }
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
}

VelocityTrainConfig LoadVelocityTrainConfig(const std::string& path, const std::vector<std::string>& overrides) {
  VelocityTrainConfig config;
  ReadConfig(LoadConfigFile(path, overrides), path + ":", config);
  ValidateVelocityTrainConfig(config, path);
  return config;
}

VelocityTrackingTask::VelocityTrackingTask(const VelocityTrainConfig& config, const Communicator& comm)
    : config_(CheckedAndSeeded(config)),
      comm_(comm),
      method_(ParseVelocityMethod(config.method)),
      library_(LoadSelectorLibrary(config)),
      shape_(SelectorShape(config)),
      num_envs_(LocalEnvCount(config.num_envs, comm)),
      steps_(config.steps_per_env),
      obs_size_(VelocityPolicyObsSize(config, library_ ? library_->num_skills() : 0)),
      env_(config.env, config.task, num_envs_, config.seed, ResolveThreadCount(config.num_threads),
           comm.rank() * num_envs_),
      streams_(config.value_streams()),
      scratch_(method_ == VelocityMethod::kScratch
                   ? ActorCritic(obs_size_, obs_size_, kActionSize, config.policy, streams_)
                   : ActorCritic(nullptr)),
      selector_(library_ ? CategoricalActorCritic(obs_size_, obs_size_, library_->num_skills(), config.policy, streams_,
                                                  /*prior_logits=*/true)
                         : CategoricalActorCritic(nullptr)),
      policy_(library_ ? std::shared_ptr<PpoPolicyImpl>(selector_.ptr())
                       : std::shared_ptr<PpoPolicyImpl>(scratch_.ptr())) {
  if (library_ && (config.env.action_filter_hz != library_->action_filter_hz() ||
                   config.env.action_filter_order != library_->action_filter_order())) {
    throw InputError("env.action_filter_hz and action_filter_order: " + std::to_string(config.env.action_filter_hz) +
                     " Hz of order " + std::to_string(config.env.action_filter_order) + ", but the skills of " +
                     library_->path() + " were trained behind a " + std::to_string(library_->action_filter_hz()) +
                     " Hz target filter of order " + std::to_string(library_->action_filter_order()) +
                     " (0 Hz: none); the selector must run them behind the same");
  }
  const int n = num_envs_, t = steps_;
  if (library_) {
    skill_runners_.reserve(n);
    priors_.reserve(n);
    for (int i = 0; i < n; ++i) {
      skill_runners_.emplace_back(*library_);
      priors_.emplace_back(*library_, shape_.nearest_prior_temperature, shape_.time_sharing_prior);
    }
    if (config.mirror) {
      mirror_prior_.emplace(*library_, shape_.nearest_prior_temperature, 0.0);
      rollout_commands_ = torch::zeros({t, n, 3}, torch::kFloat64);
      rollout_skills_ = torch::zeros({t, n, 2}, torch::kLong);
    }
  }
  // A selector's running skill; a semi-MDP reward's window (the scratch policy's too).
  if (library_ || config.semi_mdp.enabled()) {
    memories_.assign(n, SelectorMemory(std::max(1, shape_.memory_window_steps)));
  }
  previous_action_.assign(n * kActionSize, 0.0f);
  joint_actions_.assign(n * kActionSize, 0.0f);
  task_obs_.assign(n * kTaskObsSize, 0.0f);
  episode_return_.assign(n, 0.0);
  episode_length_.assign(n, 0);
  ended_.assign(n, 0);
  last_choice_.assign(n, -1);
}

RolloutShape VelocityTrackingTask::shape() const {
  const bool selector = method_ == VelocityMethod::kSelector;
  // The critic sees what the actor sees.
  return {steps_, num_envs_, obs_size_, obs_size_, selector ? 1 : kActionSize,
          selector ? library_->num_skills() : 2 * kActionSize, streams_};
}

void VelocityTrackingTask::Observe(torch::Tensor& raw) {
  env_.WriteTaskObservations(task_obs_.data());
  float* out = raw.data_ptr<float>();
  for (int i = 0; i < num_envs_; ++i) {
    float* row = out + i * obs_size_;
    std::copy(&task_obs_[i * kTaskObsSize], &task_obs_[(i + 1) * kTaskObsSize], row);
    if (method_ == VelocityMethod::kScratch) {
      std::copy(&previous_action_[i * kActionSize], &previous_action_[(i + 1) * kActionSize], row + kTaskObsSize);
      continue;
    }
    // As LearnedSelector builds its input (selector.cc), and the prior after it.
    const int skills = library_->num_skills(), inputs = shape_.inputs(skills);
    if (shape_.memory_window_steps > 0) memories_[i].WriteFeatures(skills, row + kTaskObsSize);
    priors_[i].Write(env_.command(i).data(), memories_[i].previous(), memories_[i].running(), row + inputs);
  }
}

// The joint actions for this step: the chosen skill's (the frozen low-level policy, run as the
// server runs it), or the scratch policy's own.
void VelocityTrackingTask::JointActions(const torch::Tensor& policy_action) {
  const float* chosen = policy_action.data_ptr<float>();
  if (method_ == VelocityMethod::kScratch) {
    std::copy(chosen, chosen + num_envs_ * kActionSize, joint_actions_.begin());
    return;
  }
  const float* motion = env_.vec_env().motion_obs();
  env_.vec_env().pool().ParallelFor(num_envs_, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      skill_runners_[i].Act(motion + i * kMotionObsSize, &previous_action_[i * kActionSize], static_cast<int>(chosen[i]),
                            &joint_actions_[i * kActionSize]);
    }
  });
}

void VelocityTrackingTask::BeginRollout() { sums_ = Sums{}; }

void VelocityTrackingTask::Step(int t, const torch::Tensor& action, Rollout& rollout) {
  if (rollout_commands_.defined()) {
    double* commands = rollout_commands_[t].data_ptr<double>();
    int64_t* skills = rollout_skills_[t].data_ptr<int64_t>();
    for (int i = 0; i < num_envs_; ++i) {
      Eigen::Map<Eigen::Vector3d>(commands + 3 * i) = env_.command(i);
      skills[2 * i] = memories_[i].previous();
      skills[2 * i + 1] = memories_[i].running();
    }
  }
  // One decision: the choice holds for decision_interval control steps, whose rewards it earns
  // until its episode ends. Steps after such an end belong to the next episode (which they start
  // under the old choice) and are not this transition's.
  float* rewards = rollout.rewards[t].data_ptr<float>();
  float* dones = rollout.dones[t].data_ptr<float>();
  float* timeouts = rollout.timeouts[t].data_ptr<float>();
  std::fill(rewards, rewards + num_envs_ * streams_, 0.0f);
  std::fill(dones, dones + num_envs_, 0.0f);
  std::fill(timeouts, timeouts + num_envs_, 0.0f);
  std::fill(ended_.begin(), ended_.end(), 0);
  Sums& s = sums_;
  if (method_ == VelocityMethod::kSelector) {
    const float* choice = action.data_ptr<float>();
    for (int i = 0; i < num_envs_; ++i) {
      const int chosen = static_cast<int>(choice[i]);
      if (last_choice_[i] >= 0 && chosen != last_choice_[i]) {
        ++s.switches;
        rewards[i * streams_ + streams_ - 1] += static_cast<float>(config_.switch_penalty * a1::kControlDt);
      }
      last_choice_[i] = chosen;
    }
  }
  for (int k = 0; k < config_.decision_interval; ++k) {
    JointActions(action);
    if (!memories_.empty()) {
      const float* motion = env_.vec_env().motion_obs();
      const float* choice = action.data_ptr<float>();
      for (int i = 0; i < num_envs_; ++i) {
        const int skill = library_ ? static_cast<int>(choice[i]) : -1;
        memories_[i].Record(env_.command(i).data(), skill, motion + i * kMotionObsSize);
      }
    }
    env_.Step(joint_actions_.data());
    for (int i = 0; i < num_envs_; ++i) {
      const Termination ending = env_.vec_env().termination()[i];
      const VelocityRewardTerms& terms = env_.terms(i);
      // What the selector is paid: a semi-MDP selector's own reward, else legged_gym's.
      const float reward =
          config_.semi_mdp.enabled() ? static_cast<float>(SemiMdpReward(i, ending)) : env_.rewards()[i];
      if (!ended_[i]) {
        if (streams_ == 1) {
          rewards[i] += reward;
        } else {  // tracking, and the rest, unclipped
          const VelocityRewardTerms scaled = Scaled(terms, config_.task.reward);
          const double tracking = scaled.tracking_lin_vel + scaled.tracking_ang_vel;
          rewards[i * streams_] += static_cast<float>(tracking * a1::kControlDt);
          rewards[i * streams_ + 1] += static_cast<float>((scaled.total - tracking) * a1::kControlDt);
        }
      }
      s.reward_sum += reward;
      s.zero_rewards += reward == 0.0f;
      s.lin_sum += terms.tracking_lin_vel;
      s.ang_sum += terms.tracking_ang_vel;
      // The tracking terms are exp(-e^2 / sigma): e^2 is recovered from them exactly.
      s.lin_err2 += -std::log(std::max(terms.tracking_lin_vel, 1e-300)) * config_.task.reward.tracking_sigma;
      s.ang_err2 += -std::log(std::max(terms.tracking_ang_vel, 1e-300)) * config_.task.reward.tracking_sigma;
      episode_return_[i] += reward;
      ++episode_length_[i];
      float* previous = &previous_action_[i * kActionSize];
      if (ending != Termination::kNone) {
        if (!ended_[i]) {
          dones[i] = 1.0f;
          timeouts[i] = ending == Termination::kTimeOut ? 1.0f : 0.0f;
          ended_[i] = 1;
        }
        ++s.ended;
        s.length_sum += episode_length_[i];
        s.return_sum += episode_return_[i];
        s.falls += IsFailure(ending);
        episode_return_[i] = 0.0;
        episode_length_[i] = 0;
        last_choice_[i] = -1;
        if (!memories_.empty()) memories_[i].Reset();
        if (library_) priors_[i].Reset();
        std::fill(previous, previous + kActionSize, 0.0f);
      } else {
        std::copy(&joint_actions_[i * kActionSize], &joint_actions_[(i + 1) * kActionSize], previous);
      }
    }
  }
}

double VelocityTrackingTask::SemiMdpReward(int i, Termination ending) const {
  const RobotState& state = env_.vec_env().stepped_state(i);  // before any reset
  const Eigen::Vector3d velocity(state.base_linear_velocity.x(), state.base_linear_velocity.y(),
                                 state.base_angular_velocity.z());
  const VelocityRewardTerms scaled = Scaled(env_.terms(i), config_.task.reward);
  const double penalties = scaled.total - scaled.tracking_lin_vel - scaled.tracking_ang_vel;
  const double per_second = SelectorRewardPerSecond(config_.semi_mdp, memories_[i].WindowError(),
                                                    env_.command(i) - velocity, penalties);
  return per_second * a1::kControlDt - (IsFailure(ending) ? config_.semi_mdp.fall_penalty : 0.0);
}

void VelocityTrackingTask::FinishRollout(Rollout&, int) {
  // Over every rank's envs.
  const Sums& s = sums_;
  double sums[11] = {s.reward_sum,      double(s.zero_rewards), s.lin_sum,    s.ang_sum,      s.lin_err2,
                     s.ang_err2,        double(s.ended),        double(s.length_sum), s.return_sum, double(s.falls),
                     double(s.switches)};
  comm_.Sum(sums, 11);
  const double samples = static_cast<double>(steps_) * num_envs_ * config_.decision_interval * comm_.size();
  const double episodes = sums[6];
  VelocityTrackingStats& stats = stats_;
  stats.mean_reward = sums[0] / samples;
  stats.zero_reward_share = sums[1] / samples;
  stats.tracking_lin_vel = sums[2] / samples;
  stats.tracking_ang_vel = sums[3] / samples;
  stats.lin_vel_error = std::sqrt(sums[4] / samples);
  stats.ang_vel_error = std::sqrt(sums[5] / samples);
  stats.episodes_ended = static_cast<int>(episodes);
  stats.mean_episode_length = episodes > 0 ? sums[7] / episodes : 0.0;
  stats.mean_episode_return = episodes > 0 ? sums[8] / episodes : 0.0;
  stats.fall_fraction = episodes > 0 ? sums[9] / episodes : 0.0;
  stats.switches_per_s = sums[10] / (samples * a1::kControlDt);
}

MirroredSamples VelocityTrackingTask::Mirror(const torch::Tensor& raw_obs, const Rollout& rollout,
                                             const RunningNormalizer& normalizer) const {
  torch::NoGradGuard no_grad;
  mirror::SignedPermutation obs = mirror::TaskObservation();
  if (method_ == VelocityMethod::kScratch) {  // o^c and the previous joint action
    const mirror::SignedPermutation joints = mirror::Joints();
    for (int j = 0; j < joints.size(); ++j) {
      obs.source.push_back(kTaskObsSize + joints.source[j]);
      obs.sign.push_back(joints.sign[j]);
    }
  }
  const int64_t count = raw_obs.size(0);
  torch::Tensor mirrored = MirrorAlong(obs, raw_obs.narrow(1, 0, obs.size()), 1);
  std::vector<int64_t> pairs;
  if (library_) {  // the prior of the mirrored command (vx, -vy, -wz) after the mirrored skills
    for (const SkillDescriptor& d : library_->skills()) pairs.push_back(d.mirror_skill);
    const int skills = library_->num_skills();
    torch::Tensor prior = torch::empty({count, skills}, torch::kFloat32);
    const torch::Tensor commands = rollout_commands_.view({count, 3}).contiguous();
    const int64_t* ran = rollout_skills_.data_ptr<int64_t>();
    const auto mirrored_skill = [&](int64_t k) { return k >= 0 ? static_cast<int>(pairs[k]) : -1; };
    for (int64_t r = 0; r < count; ++r) {
      const double* c = commands.data_ptr<double>() + 3 * r;
      const double flipped[3] = {c[0], -c[1], -c[2]};
      mirror_prior_->Write(flipped, mirrored_skill(ran[2 * r]), mirrored_skill(ran[2 * r + 1]),
                           prior.data_ptr<float>() + r * skills);
    }
    mirrored = torch::cat({mirrored, prior}, 1);
  }
  MirroredSamples m;
  m.obs = NormalizeLeadingColumns(normalizer, mirrored);
  m.critic_obs = m.obs;  // the critic sees what the actor sees
  const torch::Tensor actions = rollout.actions.view({count, -1});
  if (method_ == VelocityMethod::kScratch) {
    m.actions = MirrorAlong(mirror::Joints(), actions, 1);
  } else {
    const torch::Tensor chosen = actions.squeeze(1).to(torch::kLong);
    m.actions = torch::tensor(pairs, torch::kLong).index_select(0, chosen).to(torch::kFloat32).unsqueeze(1);
  }
  return m;
}

// ---- checkpoints ----

void VelocityTrackingTask::Save(torch::serialize::OutputArchive& archive) const {
  archive.write("config", c10::IValue(ToYamlString(config_)));
  archive.write("library_fingerprint", c10::IValue(library_ ? library_->fingerprint() : std::string()));
}

void VelocityTrackingTask::Load(torch::serialize::InputArchive& archive, const std::string&) {
  const std::string fingerprint = ReadString(archive, "library_fingerprint");
  if (library_ && fingerprint != library_->fingerprint()) {
    throw InputError("the selector was trained over a library with fingerprint " + fingerprint + ", but " +
                     library_->path() + " has " + library_->fingerprint() + " (it changed since)");
  }
}

namespace {

// Reads a velocity run's policy and normaliser (and then `more` of the archive) from `checkpoint`
// into the shapes `config` makes, naming the checkpoint if it does not fit.
void ReadVelocityPolicy(const std::string& checkpoint, torch::nn::Module& policy, torch::nn::Module& normalizer,
                        int& iteration, long& env_steps,
                        const std::function<void(torch::serialize::InputArchive&)>& more = {}) {
  torch::serialize::InputArchive archive = OpenCheckpoint(checkpoint);
  try {
    ReadPolicyParts(archive, policy, normalizer, iteration, env_steps);
    if (more) more(archive);
  } catch (const c10::Error& e) {
    MismatchedCheckpoint(checkpoint, e);
  } catch (const InputError& e) {
    throw InputError(checkpoint + ": does not fit this velocity training config: " + e.what());
  }
}

}  // namespace

TrainedSelector LoadTrainedSelector(const VelocityTrainConfig& config, int num_skills, const std::string& checkpoint) {
  TrainedSelector out;
  const int obs = VelocityPolicyObsSize(config, num_skills);
  out.policy = CategoricalActorCritic(obs, obs, num_skills, config.policy, config.value_streams(), /*prior_logits=*/true);
  out.normalizer = RunningNormalizer(NormalizedVelocityObsSize(config));
  ReadVelocityPolicy(checkpoint, *out.policy, *out.normalizer, out.iteration, out.env_steps,
                     [&](torch::serialize::InputArchive& archive) {
                       out.library_fingerprint = ReadString(archive, "library_fingerprint");
                     });
  return out;
}

TrainedPolicy LoadTrainedScratch(const VelocityTrainConfig& config, const std::string& checkpoint) {
  TrainedPolicy out;
  const int obs = VelocityPolicyObsSize(config, 0);
  out.policy = ActorCritic(obs, obs, kActionSize, config.policy, config.value_streams());
  out.normalizer = RunningNormalizer(NormalizedVelocityObsSize(config));
  ReadVelocityPolicy(checkpoint, *out.policy, *out.normalizer, out.iteration, out.env_steps);
  return out;
}

// ---- progress ----

double VelocityTrackingTask::EntropyOrStd(const RunnerStats& runner) const {
  return method_ == VelocityMethod::kSelector ? runner.ppo.entropy : scratch_->Std().mean().item<double>();
}

ProgressRecord VelocityTrackingTask::Progress(const RunnerStats& runner) const {
  return VelocityProgress(runner, stats_, EntropyOrStd(runner));
}

ProgressRecord VelocityProgress(const RunnerStats& r, const VelocityTrackingStats& s, double entropy_or_std) {
  ProgressRecord record;
  record.Add("iteration", long{r.iteration})
      .Add("env_steps", r.env_steps)
      .Add("steps_per_s", r.steps_per_s, "%.1f")
      .Add("mean_reward", s.mean_reward, "%.6f")
      .Add("mean_episode_return", s.mean_episode_return, "%.4f")
      .Add("episodes_ended", long{s.episodes_ended})
      .Add("mean_episode_length", s.mean_episode_length, "%.2f")
      .Add("fall_fraction", s.fall_fraction, "%.4f")
      .Add("tracking_lin_vel", s.tracking_lin_vel, "%.5f")
      .Add("tracking_ang_vel", s.tracking_ang_vel, "%.5f")
      .Add("lin_vel_error", s.lin_vel_error, "%.5f")
      .Add("ang_vel_error", s.ang_vel_error, "%.5f")
      .Add("entropy_or_std", entropy_or_std, "%.5f")
      .Add("surrogate_loss", r.ppo.surrogate_loss, "%.6f")
      .Add("value_loss", r.ppo.value_loss, "%.6f")
      .Add("kl", r.ppo.kl, "%.6f")
      .Add("learning_rate", r.ppo.learning_rate, "%.3g")
      .Add("seconds_collect", r.seconds_collect, "%.4f")
      .Add("seconds_ppo", r.seconds_ppo, "%.4f")
      .Add("seconds_total", r.seconds_total, "%.4f")
      .Add("switches_per_s", s.switches_per_s, "%.3f")
      .Add("zero_reward_share", s.zero_reward_share, "%.4f")
      .Add("prior_kl", r.ppo.prior_kl, "%.5f");
  return record;
}

std::string VelocityTrackingTask::ProgressLine(const RunnerStats& r, int total_iterations, double eta_seconds) const {
  const VelocityTrackingStats& s = stats_;
  char line[512];
  std::snprintf(line, sizeof(line),
                "it %d/%d | %.0f steps/s | ETA %s | reward/step %.4f (zero %.0f%%) | ep len %.0f (falls %.0f%%) | "
                "v err %.3f m/s | w err %.3f rad/s | switches %.1f/s | entropy/std %.3f | lr %.1e",
                r.iteration, total_iterations, r.steps_per_s, Duration(eta_seconds).c_str(), s.mean_reward,
                100.0 * s.zero_reward_share, s.mean_episode_length, 100.0 * s.fall_fraction, s.lin_vel_error,
                s.ang_vel_error, s.switches_per_s, EntropyOrStd(r), r.ppo.learning_rate);
  return line;
}

std::array<Interval, 3> CommandEnvelope(const SkillLibrary& library, double widen) {
  const NearestSkillSelector skills(library);  // its candidates: the surviving skills
  std::array<Interval, 3> envelope;
  for (int a = 0; a < 3; ++a) {
    envelope[a] = {widen * std::min(0.0, skills.velocity_min()[a]), widen * std::max(0.0, skills.velocity_max()[a])};
  }
  return envelope;
}

}  // namespace flsd
