#include "skills/learning/runners/task_trainer.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/atomic_file.h"
#include "core/check.h"
#include "robot/mirror.h"
#include "robot/observation.h"
#include "skills/learning/runners/checkpoint_io.h"
#include "skills/learning/runners/run_loop.h"
#include "skills/learning/algorithms/symmetry.h"
#include "skills/learning/runners/training_run.h"

namespace flsd {
namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

const TaskTrainConfig& SeedTorch(const TaskTrainConfig& config) {
  torch::manual_seed(config.seed);
  return config;
}

std::optional<SkillLibrary> LoadSelectorLibrary(const TaskTrainConfig& config) {
  if (ParseTaskMethod(config.method) != TaskMethod::kSelector) return std::nullopt;
  return SkillLibrary::Load(config.library);
}

}  // namespace

TaskMethod ParseTaskMethod(const std::string& name) {
  if (name == "selector") return TaskMethod::kSelector;
  if (name == "scratch") return TaskMethod::kScratch;
  throw InputError("method: expected 'selector' or 'scratch', got '" + name + "'");
}

int NormalizedTaskObsSize(TaskMethod method) {
  return method == TaskMethod::kSelector ? kTaskObsSize : kTaskObsSize + kActionSize;
}

int TaskPolicyObsSize(const TaskTrainConfig& config, int num_skills) {
  const TaskMethod method = ParseTaskMethod(config.method);
  return NormalizedTaskObsSize(method) + (method == TaskMethod::kSelector && config.nearest_prior() ? num_skills : 0);
}

void ValidateTaskTrainConfig(const TaskTrainConfig& config, const std::string& where) {
  try {
    const TaskMethod method = ParseTaskMethod(config.method);
    if (method == TaskMethod::kSelector && config.library.empty()) {
      throw InputError("library: the selector needs a skill library to choose from (models/*.safetensors)");
    }
    if (method == TaskMethod::kScratch && config.nearest_prior()) {
      throw InputError("nearest_prior_temperature: a prior over skills needs method 'selector'; expected 0");
    }
    if (method == TaskMethod::kScratch && config.decision_interval != 1) {
      throw InputError("decision_interval: the scratch policy acts every control step; expected 1, got " +
                       std::to_string(config.decision_interval));
    }
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
}

TaskTrainConfig LoadTaskTrainConfig(const std::string& path, const std::vector<std::string>& overrides) {
  TaskTrainConfig config;
  ReadConfig(LoadConfigFile(path, overrides), path + ":", config);
  ValidateTaskTrainConfig(config, path);
  return config;
}

TaskTrainer::TaskTrainer(const TaskTrainConfig& config, const Communicator& comm)
    : config_(SeedTorch(config)),
      comm_(comm),
      method_(ParseTaskMethod(config.method)),
      library_(LoadSelectorLibrary(config)),
      nearest_(library_ && config.nearest_prior() ? std::make_optional<NearestSkillSelector>(*library_) : std::nullopt),
      num_envs_(LocalEnvCount(config.num_envs, comm)),
      steps_(config.steps_per_env),
      obs_size_(TaskPolicyObsSize(config, library_ ? library_->num_skills() : 0)),
      task_(config.env, config.task, num_envs_, config.seed, ResolveThreadCount(config.num_threads),
            comm.rank() * num_envs_),
      streams_(config.value_streams()),
      scratch_(method_ == TaskMethod::kScratch
                   ? ActorCritic(obs_size_, obs_size_, kActionSize, config.policy, streams_)
                   : ActorCritic(nullptr)),
      selector_(library_ ? CategoricalActorCritic(obs_size_, obs_size_, library_->num_skills(), config.policy, streams_,
                                                  config.nearest_prior())
                         : CategoricalActorCritic(nullptr)),
      policy_(library_ ? std::shared_ptr<PpoPolicyImpl>(selector_.ptr()) : std::shared_ptr<PpoPolicyImpl>(scratch_.ptr())),
      learner_(policy_, NormalizedTaskObsSize(method_), config.ppo, config.seed, comm),
      rollout_(learner_.rollout()) {
  ValidateTaskTrainConfig(config, "task training config");
  if (library_ && (config.env.action_filter_hz != library_->action_filter_hz() ||
                   config.env.action_filter_order != library_->action_filter_order())) {
    throw InputError("env.action_filter_hz and action_filter_order: " + std::to_string(config.env.action_filter_hz) +
                     " Hz of order " + std::to_string(config.env.action_filter_order) + ", but the skills of " +
                     library_->path() + " were trained behind a " + std::to_string(library_->action_filter_hz()) +
                     " Hz target filter of order " + std::to_string(library_->action_filter_order()) +
                     " (0 Hz: none); the selector must run them behind the same");
  }
  SeedRankStreams(config.seed, comm);
  const int n = num_envs_, t = steps_;
  if (library_) {
    skill_runners_.reserve(n);
    for (int i = 0; i < n; ++i) skill_runners_.emplace_back(*library_);
  }
  previous_action_.assign(n * kActionSize, 0.0f);
  joint_actions_.assign(n * kActionSize, 0.0f);
  task_obs_.assign(n * kTaskObsSize, 0.0f);
  episode_return_.assign(n, 0.0);
  episode_length_.assign(n, 0);
  ended_.assign(n, 0);
  last_choice_.assign(n, -1);
  const auto f = torch::kFloat32;
  const bool selector = method_ == TaskMethod::kSelector;
  // The critic sees what the actor sees.
  learner_.AllocateRollout({t, n, obs_size_, obs_size_, selector ? 1 : kActionSize,
                            selector ? library_->num_skills() : 2 * kActionSize, streams_});
  raw_obs_ = torch::zeros({n, obs_size_}, f);
  if (config.mirror) raw_rollout_obs_ = torch::zeros({t, n, obs_size_}, f);
  if (nearest_) {
    commands_ = torch::zeros({n, 3}, torch::kFloat64);
    if (config.mirror) rollout_commands_ = torch::zeros({t, n, 3}, torch::kFloat64);
  }
}

torch::Tensor TaskTrainer::PriorLogits(const torch::Tensor& commands) const {
  const torch::Tensor c = commands.contiguous();
  torch::Tensor prior = torch::empty({c.size(0), library_->num_skills()}, torch::kFloat32);
  const int64_t skills = prior.size(1);
  for (int64_t i = 0; i < c.size(0); ++i) {
    nearest_->Prior(c.data_ptr<double>() + 3 * i, config_.nearest_prior_temperature, prior.data_ptr<float>() + i * skills);
  }
  return prior;
}

torch::Tensor TaskTrainer::Observations(bool update_normalizer) {
  task_.WriteTaskObservations(task_obs_.data());
  float* raw = raw_obs_.data_ptr<float>();
  for (int i = 0; i < num_envs_; ++i) {
    float* row = raw + i * obs_size_;
    std::copy(&task_obs_[i * kTaskObsSize], &task_obs_[(i + 1) * kTaskObsSize], row);
    if (method_ == TaskMethod::kScratch) {
      std::copy(&previous_action_[i * kActionSize], &previous_action_[(i + 1) * kActionSize], row + kTaskObsSize);
    }
  }
  if (nearest_) {
    double* commands = commands_.data_ptr<double>();
    for (int i = 0; i < num_envs_; ++i) Eigen::Map<Eigen::Vector3d>(commands + 3 * i) = task_.command(i);
    raw_obs_.narrow(1, kTaskObsSize, library_->num_skills()).copy_(PriorLogits(commands_));
  }
  const int normalized = NormalizedTaskObsSize(method_);
  if (update_normalizer) learner_.UpdateNormalizer(raw_obs_.narrow(1, 0, normalized));
  return NormalizeLeadingColumns(learner_.normalizer(), raw_obs_);
}

// The joint actions for this step: the chosen skill's (the frozen low-level policy, run as the
// server runs it), or the scratch policy's own.
void TaskTrainer::JointActions(const torch::Tensor& policy_action) {
  const float* chosen = policy_action.data_ptr<float>();
  if (method_ == TaskMethod::kScratch) {
    std::copy(chosen, chosen + num_envs_ * kActionSize, joint_actions_.begin());
    return;
  }
  const float* motion = task_.vec_env().motion_obs();
  task_.vec_env().pool().ParallelFor(num_envs_, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      skill_runners_[i].Act(motion + i * kMotionObsSize, &previous_action_[i * kActionSize], static_cast<int>(chosen[i]),
                            &joint_actions_[i * kActionSize]);
    }
  });
}

void TaskTrainer::Collect(TaskIterationStats& stats) {
  torch::NoGradGuard no_grad;
  long ended = 0, length_sum = 0, falls = 0, switches = 0;
  long zero_rewards = 0;  // steps the clip at zero left without any gradient
  double return_sum = 0.0, reward_sum = 0.0, lin_sum = 0.0, ang_sum = 0.0, lin_err2 = 0.0, ang_err2 = 0.0;
  for (int t = 0; t < steps_; ++t) {
    const torch::Tensor obs = Observations(/*update_normalizer=*/true);
    const torch::Tensor distribution = policy_->Distribution(obs);
    const torch::Tensor action = policy_->Sample(distribution);
    rollout_.obs[t].copy_(obs);
    if (raw_rollout_obs_.defined()) raw_rollout_obs_[t].copy_(raw_obs_);
    if (rollout_commands_.defined()) rollout_commands_[t].copy_(commands_);
    rollout_.actions[t].copy_(action);
    rollout_.distributions[t].copy_(distribution);
    rollout_.log_probs[t].copy_(policy_->LogProb(distribution, action));
    rollout_.values[t].copy_(policy_->Value(obs));

    // One decision: the choice holds for decision_interval control steps, whose rewards it
    // earns until its episode ends. Steps after such an end belong to the next episode (which
    // they start under the old choice) and are not this transition's.
    float* rewards = rollout_.rewards[t].data_ptr<float>();
    float* dones = rollout_.dones[t].data_ptr<float>();
    float* timeouts = rollout_.timeouts[t].data_ptr<float>();
    std::fill(rewards, rewards + num_envs_ * streams_, 0.0f);
    std::fill(dones, dones + num_envs_, 0.0f);
    std::fill(timeouts, timeouts + num_envs_, 0.0f);
    std::fill(ended_.begin(), ended_.end(), 0);
    if (method_ == TaskMethod::kSelector) {
      const float* choice = action.data_ptr<float>();
      for (int i = 0; i < num_envs_; ++i) {
        const int chosen = static_cast<int>(choice[i]);
        if (last_choice_[i] >= 0 && chosen != last_choice_[i]) {
          ++switches;
          rewards[i * streams_ + streams_ - 1] += static_cast<float>(config_.switch_penalty * a1::kControlDt);
        }
        last_choice_[i] = chosen;
      }
    }
    for (int k = 0; k < config_.decision_interval; ++k) {
      JointActions(action);
      task_.Step(joint_actions_.data());
      for (int i = 0; i < num_envs_; ++i) {
        const Termination ending = task_.vec_env().termination()[i];
        const VelocityRewardTerms& terms = task_.terms(i);
        const float reward = task_.rewards()[i];
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
        reward_sum += reward;
        zero_rewards += reward == 0.0f;
        lin_sum += terms.tracking_lin_vel;
        ang_sum += terms.tracking_ang_vel;
        // The tracking terms are exp(-e^2 / sigma): e^2 is recovered from them exactly.
        lin_err2 += -std::log(std::max(terms.tracking_lin_vel, 1e-300)) * config_.task.reward.tracking_sigma;
        ang_err2 += -std::log(std::max(terms.tracking_ang_vel, 1e-300)) * config_.task.reward.tracking_sigma;
        episode_return_[i] += reward;
        ++episode_length_[i];
        float* previous = &previous_action_[i * kActionSize];
        if (ending != Termination::kNone) {
          if (!ended_[i]) {
            dones[i] = 1.0f;
            timeouts[i] = ending == Termination::kTimeOut ? 1.0f : 0.0f;
            ended_[i] = 1;
          }
          ++ended;
          length_sum += episode_length_[i];
          return_sum += episode_return_[i];
          falls += IsFailure(ending);
          episode_return_[i] = 0.0;
          episode_length_[i] = 0;
          last_choice_[i] = -1;
          std::fill(previous, previous + kActionSize, 0.0f);
        } else {
          std::copy(&joint_actions_[i * kActionSize], &joint_actions_[(i + 1) * kActionSize], previous);
        }
      }
    }
  }
  last_values_ = policy_->Value(Observations(/*update_normalizer=*/false));
  // Over every rank's envs.
  double sums[11] = {reward_sum,        double(zero_rewards), lin_sum,     ang_sum,       lin_err2,        ang_err2,
                     double(ended),     double(length_sum),   return_sum,  double(falls), double(switches)};
  comm_.Sum(sums, 11);
  const double samples = static_cast<double>(steps_) * num_envs_ * config_.decision_interval * comm_.size();
  const double episodes = sums[6];
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

MirroredSamples TaskTrainer::MirroredRollout() const {
  torch::NoGradGuard no_grad;
  mirror::SignedPermutation obs = mirror::TaskObservation();
  if (method_ == TaskMethod::kScratch) {  // o^c and the previous joint action
    const mirror::SignedPermutation joints = mirror::Joints();
    for (int j = 0; j < joints.size(); ++j) {
      obs.source.push_back(kTaskObsSize + joints.source[j]);
      obs.sign.push_back(joints.sign[j]);
    }
  }
  const int64_t count = raw_rollout_obs_.size(0) * raw_rollout_obs_.size(1);
  const torch::Tensor raw = raw_rollout_obs_.view({count, obs_size_});
  torch::Tensor mirrored = MirrorAlong(obs, raw.narrow(1, 0, obs.size()), 1);
  if (nearest_) {  // the prior of the mirrored command (vx, -vy, -wz)
    const torch::Tensor flip = torch::tensor({1.0, -1.0, -1.0}, torch::kFloat64);
    mirrored = torch::cat({mirrored, PriorLogits(rollout_commands_.view({count, 3}) * flip)}, 1);
  }
  MirroredSamples m;
  m.obs = NormalizeLeadingColumns(learner_.normalizer(), mirrored);
  m.critic_obs = m.obs;  // the critic sees what the actor sees
  const torch::Tensor actions = rollout_.actions.view({count, -1});
  if (method_ == TaskMethod::kScratch) {
    m.actions = MirrorAlong(mirror::Joints(), actions, 1);
  } else {
    std::vector<int64_t> pairs;
    for (const SkillDescriptor& d : library_->skills()) pairs.push_back(d.mirror_skill);
    const torch::Tensor chosen = actions.squeeze(1).to(torch::kLong);
    m.actions = torch::tensor(pairs, torch::kLong).index_select(0, chosen).to(torch::kFloat32).unsqueeze(1);
  }
  return m;
}

TaskIterationStats TaskTrainer::RunIteration() {
  TaskIterationStats stats;
  const Clock::time_point start = Clock::now();
  Collect(stats);
  stats.seconds_collect = Since(start);
  const Clock::time_point phase = Clock::now();
  if (config_.mirror) {
    const MirroredSamples mirrored = MirroredRollout();
    stats.ppo = learner_.Update(last_values_, &mirrored);
  } else {
    stats.ppo = learner_.Update(last_values_);
  }
  stats.seconds_ppo = Since(phase);
  const long job_steps = static_cast<long>(steps_) * num_envs_ * config_.decision_interval * comm_.size();
  learner_.CountIteration(job_steps);
  stats.iteration = learner_.iteration();
  stats.env_steps = learner_.env_steps();
  stats.entropy_or_std = method_ == TaskMethod::kSelector ? stats.ppo.entropy : scratch_->Std().mean().item<double>();
  stats.seconds_total = Since(start);
  stats.steps_per_s = job_steps / stats.seconds_total;
  stats.finite = stats.ppo.finite;
  return stats;
}

// ---- checkpoints ----

void TaskTrainer::SaveCheckpoint(const std::string& path) const {
  torch::serialize::OutputArchive archive;
  learner_.Write(archive, task_.command_rngs(), "command_rng");
  archive.write("config", c10::IValue(ToYamlString(config_)));
  archive.write("library_fingerprint", c10::IValue(library_ ? library_->fingerprint() : std::string()));
  WriteFileAtomically(path, [&](const std::string& temp) { archive.save_to(temp); });
}

void TaskTrainer::LoadCheckpoint(const std::string& path) {
  torch::serialize::InputArchive archive = OpenCheckpoint(path);
  try {
    const std::string fingerprint = ReadString(archive, "library_fingerprint");
    if (library_ && fingerprint != library_->fingerprint()) {
      throw InputError("the selector was trained over a library with fingerprint " + fingerprint + ", but " +
                       library_->path() + " has " + library_->fingerprint() + " (it changed since)");
    }
    learner_.Read(archive, task_.command_rngs(), "command_rng", config_.seed + VelocityTask::kCommandStream,
                  comm_.rank() * num_envs_);
  } catch (const c10::Error& e) {
    MismatchedCheckpoint(path, e);
  } catch (const InputError& e) {
    throw InputError(path + ": does not fit this task config: " + e.what());
  }
}

TrainedSelector LoadTrainedSelector(const TaskTrainConfig& config, int num_skills, const std::string& checkpoint) {
  torch::serialize::InputArchive archive = OpenCheckpoint(checkpoint);
  TrainedSelector out;
  const int obs = TaskPolicyObsSize(config, num_skills);
  out.policy =
      CategoricalActorCritic(obs, obs, num_skills, config.policy, config.value_streams(), config.nearest_prior());
  out.normalizer = RunningNormalizer(NormalizedTaskObsSize(TaskMethod::kSelector));
  try {
    ReadPolicyParts(archive, *out.policy, *out.normalizer, out.iteration, out.env_steps);
    out.library_fingerprint = ReadString(archive, "library_fingerprint");
  } catch (const c10::Error& e) {
    MismatchedCheckpoint(checkpoint, e);
  } catch (const InputError& e) {
    throw InputError(checkpoint + ": does not fit this task config: " + e.what());
  }
  return out;
}

// ---- progress ----

ProgressRecord TaskProgress(const TaskIterationStats& s) {
  ProgressRecord r;
  r.Add("iteration", long{s.iteration})
      .Add("env_steps", s.env_steps)
      .Add("steps_per_s", s.steps_per_s, "%.1f")
      .Add("mean_reward", s.mean_reward, "%.6f")
      .Add("mean_episode_return", s.mean_episode_return, "%.4f")
      .Add("episodes_ended", long{s.episodes_ended})
      .Add("mean_episode_length", s.mean_episode_length, "%.2f")
      .Add("fall_fraction", s.fall_fraction, "%.4f")
      .Add("tracking_lin_vel", s.tracking_lin_vel, "%.5f")
      .Add("tracking_ang_vel", s.tracking_ang_vel, "%.5f")
      .Add("lin_vel_error", s.lin_vel_error, "%.5f")
      .Add("ang_vel_error", s.ang_vel_error, "%.5f")
      .Add("entropy_or_std", s.entropy_or_std, "%.5f")
      .Add("surrogate_loss", s.ppo.surrogate_loss, "%.6f")
      .Add("value_loss", s.ppo.value_loss, "%.6f")
      .Add("kl", s.ppo.kl, "%.6f")
      .Add("learning_rate", s.ppo.learning_rate, "%.3g")
      .Add("seconds_collect", s.seconds_collect, "%.4f")
      .Add("seconds_ppo", s.seconds_ppo, "%.4f")
      .Add("seconds_total", s.seconds_total, "%.4f")
      .Add("switches_per_s", s.switches_per_s, "%.3f")
      .Add("zero_reward_share", s.zero_reward_share, "%.4f");
  return r;
}

std::string TaskProgressLine(const TaskIterationStats& s, int total_iterations, double eta_seconds) {
  char line[512];
  std::snprintf(line, sizeof(line),
                "it %d/%d | %.0f steps/s | ETA %s | reward/step %.4f (zero %.0f%%) | ep len %.0f (falls %.0f%%) | "
                "v err %.3f m/s | w err %.3f rad/s | switches %.1f/s | entropy/std %.3f | lr %.1e",
                s.iteration, total_iterations, s.steps_per_s, Duration(eta_seconds).c_str(), s.mean_reward,
                100.0 * s.zero_reward_share, s.mean_episode_length, 100.0 * s.fall_fraction, s.lin_vel_error, s.ang_vel_error,
                s.switches_per_s, s.entropy_or_std, s.ppo.learning_rate);
  return line;
}

// ---- the run ----

std::array<Interval, 3> CommandEnvelope(const SkillLibrary& library, double widen) {
  const NearestSkillSelector skills(library);  // its candidates: the surviving skills
  std::array<Interval, 3> envelope;
  for (int a = 0; a < 3; ++a) {
    envelope[a] = {widen * std::min(0.0, skills.velocity_min()[a]), widen * std::max(0.0, skills.velocity_max()[a])};
  }
  return envelope;
}

int RunTaskTraining(const TaskRunOptions& options, const std::atomic<bool>& stop_requested) {
  const RunFolder folder = OpenRunFolder(options.run_dir, options.resume);
  if (options.resume && (!options.method.empty() || !options.library.empty() || !options.overrides.empty())) {
    throw InputError("--method, --library and --set set up a new run; a resumed run keeps its own (" +
                     folder.config_file + ")");
  }
  TaskTrainConfig config = LoadTaskTrainConfig(options.resume ? folder.config_file : options.config_path, options.overrides);
  if (!options.method.empty()) config.method = options.method;
  if (!options.library.empty()) config.library = options.library;
  if (options.iterations > 0) config.iterations = options.iterations;
  if (options.threads > 0) config.num_threads = options.threads;
  ValidateTaskTrainConfig(config, folder.config_file);
  // A new selector runs its skills behind the target filter they were trained with.
  if (!options.resume && ParseTaskMethod(config.method) == TaskMethod::kSelector) {
    const SkillLibrary library = SkillLibrary::Load(config.library);
    config.env.action_filter_hz = library.action_filter_hz();
    config.env.action_filter_order = library.action_filter_order();
    VelocityCommandConfig& commands = config.task.commands;
    if (commands.library_envelope > 0.0) {
      const std::array<Interval, 3> envelope = CommandEnvelope(library, commands.library_envelope);
      commands.vx = envelope[0];
      commands.vy = envelope[1];
      commands.wz = envelope[2];
    }
    if (commands.skill_share > 0.0) {
      commands.skill_velocities.clear();
      const NearestSkillSelector dependable(library);
      for (const Eigen::Vector3d& v : dependable.velocities()) {
        commands.skill_velocities.insert(commands.skill_velocities.end(), {v.x(), v.y(), v.z()});
      }
    }
  }
  const Communicator& comm =
      StartRun(folder, ToYamlString(config), options.resume, config.num_envs, config.num_threads);
  TaskTrainer trainer(config, comm);
  if (options.resume) {
    trainer.LoadCheckpoint(folder.checkpoint);
    spdlog::info("resumed {} at iteration {} ({} env steps)", options.run_dir, trainer.iteration(), trainer.env_steps());
  } else {
    spdlog::info("new velocity-task run ({}{}) in {}: {} envs x {} steps per iteration, {} iterations", config.method,
                 trainer.library() ? " over " + config.library : std::string(), options.run_dir, config.num_envs,
                 config.steps_per_env, config.iterations);
  }
  return RunIterations(
      trainer, comm, folder, TaskProgress(TaskIterationStats{}).header(), config.iterations, config.checkpoint_every, 0,
      stop_requested,
      [](const TaskIterationStats& s) { return TaskProgress(s).row(); },
      [&](const TaskIterationStats& s, double eta) { return TaskProgressLine(s, config.iterations, eta); });
}

}  // namespace flsd
