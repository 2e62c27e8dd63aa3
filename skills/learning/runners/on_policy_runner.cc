#include "skills/learning/runners/on_policy_runner.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <optional>

#include "core/atomic_file.h"
#include "core/check.h"
#include "skills/learning/runners/checkpoint_io.h"

namespace flsd {
namespace {

using Clock = std::chrono::steady_clock;
double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace

OnPolicyRunner::OnPolicyRunner(RolloutTask& task, const PpoConfig& ppo, uint64_t seed, const Communicator& comm)
    : task_(task),
      comm_(comm),
      policy_(task.policy()),
      learner_(policy_, task.normalized_obs(), ppo, seed, comm),
      rollout_(learner_.rollout()) {
  // Every rank drew the same initial parameters from the seed; from here each draws its own
  // actions and minibatches.
  SeedRankStreams(seed, comm);
  const RolloutShape shape = task.shape();
  learner_.AllocateRollout(shape);
  raw_obs_ = torch::zeros({shape.envs, shape.obs}, torch::kFloat32);
  if (task.mirrored()) raw_rollout_obs_ = torch::zeros({shape.steps, shape.envs, shape.obs}, torch::kFloat32);
}

torch::Tensor OnPolicyRunner::Observe(bool update_normalizer) {
  task_.Observe(raw_obs_);
  if (update_normalizer) learner_.UpdateNormalizer(raw_obs_.slice(1, 0, task_.normalized_obs()));
  return NormalizeLeadingColumns(learner_.normalizer(), raw_obs_);
}

void OnPolicyRunner::Collect(RunnerStats& stats) {
  torch::NoGradGuard no_grad;
  const Clock::time_point collect = Clock::now();
  const bool separate_critic = !rollout_.critic_obs.is_same(rollout_.obs);
  task_.BeginRollout();
  for (int t = 0; t < rollout_.obs.size(0); ++t) {
    const Clock::time_point start = Clock::now();
    const torch::Tensor obs = Observe(/*update_normalizer=*/true);
    const torch::Tensor critic_obs = task_.CriticObservations(obs);
    const torch::Tensor distribution = policy_->Distribution(obs);
    const torch::Tensor action = policy_->Sample(distribution);
    rollout_.obs[t].copy_(obs);
    if (separate_critic) rollout_.critic_obs[t].copy_(critic_obs);
    if (raw_rollout_obs_.defined()) raw_rollout_obs_[t].copy_(raw_obs_);
    rollout_.actions[t].copy_(action);
    rollout_.distributions[t].copy_(distribution);
    rollout_.log_probs[t].copy_(policy_->LogProb(distribution, action));
    rollout_.values[t].copy_(policy_->Value(critic_obs));
    stats.seconds_policy += Since(start);
    task_.Step(t, action, rollout_);
  }
  const Clock::time_point start = Clock::now();
  last_values_ = policy_->Value(task_.CriticObservations(Observe(/*update_normalizer=*/false)));
  stats.seconds_policy += Since(start);
  stats.seconds_collect = Since(collect);
}

RunnerStats OnPolicyRunner::RunIteration() {
  RunnerStats stats;
  const Clock::time_point start = Clock::now();
  Collect(stats);

  Clock::time_point phase = Clock::now();
  task_.FinishRollout(rollout_, learner_.iteration());
  stats.seconds_finish = Since(phase);

  phase = Clock::now();
  if (task_.mirrored()) {
    const int64_t count = raw_rollout_obs_.size(0) * raw_rollout_obs_.size(1);
    const MirroredSamples mirrored =
        task_.Mirror(raw_rollout_obs_.view({count, raw_rollout_obs_.size(2)}), rollout_, learner_.normalizer());
    stats.ppo = learner_.Update(last_values_, &mirrored);
  } else {
    stats.ppo = learner_.Update(last_values_);
  }
  stats.seconds_ppo = Since(phase);

  const bool auxiliaries_finite = task_.UpdateAuxiliaries();

  const RolloutShape shape = task_.shape();
  const long job_steps = static_cast<long>(shape.steps) * shape.envs * task_.control_steps_per_step() * comm_.size();
  learner_.CountIteration(job_steps);
  stats.iteration = learner_.iteration();
  stats.env_steps = learner_.env_steps();
  stats.collectives = comm_.TakeTally();
  stats.seconds_total = Since(start);
  stats.steps_per_s = job_steps / stats.seconds_total;
  stats.finite = stats.ppo.finite && auxiliaries_finite;
  if (!stats.ppo.finite) spdlog::error("iteration {}: PPO's loss is not finite", stats.iteration);
  return stats;
}

int OnPolicyRunner::Learn(const RunFolder& folder, const LearnSchedule& schedule,
                          const std::atomic<bool>& stop_requested) {
  std::optional<ProgressLog> log;
  if (comm_.leader()) log.emplace(folder.progress, task_.Progress(RunnerStats{}).header(), iteration());
  double seconds_per_iteration = 0.0;
  int saved_iteration = iteration();
  bool stopped = false;
  while (iteration() < schedule.iterations && !(stopped = comm_.Any(stop_requested))) {
    const RunnerStats stats = RunIteration();
    if (!stats.finite) {
      spdlog::error("iteration {}: a loss became NaN or infinite; stopping. {} is kept as it was at iteration {}",
                    stats.iteration, folder.checkpoint, saved_iteration);
      return 3;
    }
    if (!comm_.leader()) continue;
    log->Append(task_.Progress(stats).row());
    seconds_per_iteration = seconds_per_iteration == 0.0 ? stats.seconds_total
                                                         : 0.9 * seconds_per_iteration + 0.1 * stats.seconds_total;
    spdlog::info("{}", task_.ProgressLine(stats, schedule.iterations,
                                          seconds_per_iteration * (schedule.iterations - stats.iteration)));
    const bool keep = schedule.keep_every > 0 && stats.iteration % schedule.keep_every == 0;
    if (stats.iteration % schedule.checkpoint_every == 0 || keep) {
      SaveCheckpoint(folder.checkpoint);
      saved_iteration = stats.iteration;
    }
    if (keep) KeepCheckpoint(folder, stats.iteration);
    if (keep && schedule.after_keep) schedule.after_keep(stats.iteration);
  }
  if (!comm_.leader()) return 0;
  if (saved_iteration != iteration()) SaveCheckpoint(folder.checkpoint);
  spdlog::info("{} at iteration {}; checkpoint {}", stopped ? "stopped" : "finished", iteration(), folder.checkpoint);
  return 0;
}

void OnPolicyRunner::SaveCheckpoint(const std::string& path) const {
  torch::serialize::OutputArchive archive;
  learner_.Write(archive, task_.env_streams(), task_.env_streams_key());
  task_.Save(archive);
  WriteFileAtomically(path, [&](const std::string& temp) { archive.save_to(temp); });
}

void OnPolicyRunner::LoadCheckpoint(const std::string& path) {
  torch::serialize::InputArchive archive = OpenCheckpoint(path);
  try {
    task_.Load(archive, path);  // first: a task that was trained over another library says so
    learner_.Read(archive, task_.env_streams(), task_.env_streams_key(), task_.env_streams_seed(),
                  comm_.rank() * task_.shape().envs);
  } catch (const c10::Error& e) {
    MismatchedCheckpoint(path, e);
  } catch (const InputError& e) {
    throw InputError(path + ": does not fit this run's config: " + e.what());
  }
}

}  // namespace flsd
