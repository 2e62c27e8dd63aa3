#include "skills/learning/runners/training_run.h"

#include <dlfcn.h>
#include <malloc.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "core/check.h"
#include "core/thread_pool.h"
#include "skills/learning/evaluation/evaluation.h"
#include "skills/learning/runners/on_policy_runner.h"
#include "skills/learning/runners/policy_learner.h"
#include "skills/learning/tasks/skill_discovery_task.h"
#include "skills/learning/tasks/velocity_tracking_task.h"

namespace flsd {

void ConfigureLearningProcess(int threads) {
  using SetThreads = void (*)(int);
  if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set(1);
  torch::set_num_threads(ResolveThreadCount(threads));
  // glibc serves blocks over 32 MB with fresh mmap pages, zero-filled on first touch, and unmaps
  // them on free: every large tensor of an update paid its page faults again.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
}

void WarnIfOversubscribed(int threads) {
  std::ifstream loadavg("/proc/loadavg");
  double load = 0.0;
  if (!(loadavg >> load)) return;
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  const int wanted = ResolveThreadCount(threads);
  if (wanted > 1 && cores > 0 && load + wanted > cores + 0.5) {  // one thread has nothing to give up
    spdlog::warn("{} threads on {} cores with a load of {:.1f} already: runs side by side should split the cores "
                 "(--threads {})",
                 wanted, cores, load, std::max(1, cores - static_cast<int>(load + 0.5)));
  }
}

const Communicator& StartRun(const RunFolder& folder, const std::string& config_yaml, bool resume, int num_envs,
                             int threads, const std::string& from_checkpoint) {
  const Communicator& comm = Communicator::World();
  const int local_envs = LocalEnvCount(num_envs, comm);
  if (comm.leader()) {
    RecordRunStart(folder, config_yaml, resume, from_checkpoint);
  } else {
    spdlog::set_level(spdlog::level::warn);  // the leader speaks for the job
  }
  ConfigureLearningProcess(threads);
  if (comm.size() == 1) {
    WarnIfOversubscribed(threads);
  } else {
    spdlog::info("{} ranks, {} envs and {} threads each", comm.size(), local_envs, threads);
  }
  return comm;
}

namespace {

// Every training command's tail: the runner over `task` resumes the folder's checkpoint, or starts
// from another run's, or from scratch (`new_run` says what starts), then learns.
int Train(RolloutTask& task, const PpoConfig& ppo, uint64_t seed, const Communicator& comm, const RunFolder& folder,
          bool resume, const std::string& from_checkpoint, const std::string& new_run, const LearnSchedule& schedule,
          const std::atomic<bool>& stop_requested) {
  OnPolicyRunner runner(task, ppo, seed, comm);
  if (resume) {
    runner.LoadCheckpoint(folder.checkpoint);
    spdlog::info("resumed {} at iteration {} ({} env steps)", folder.dir, runner.iteration(), runner.env_steps());
  } else if (!from_checkpoint.empty()) {
    runner.LoadCheckpoint(from_checkpoint);
    spdlog::info("{} from {} at iteration {} ({} env steps)", new_run, from_checkpoint, runner.iteration(),
                 runner.env_steps());
  } else {
    spdlog::info("{}", new_run);
  }
  return runner.Learn(folder, schedule, stop_requested);
}

}  // namespace

int RunTraining(const TrainingRunOptions& options, const std::atomic<bool>& stop_requested) {
  const RunFolder folder = OpenRunFolder(options.run_dir, options.resume);
  if (options.resume && !options.from_checkpoint.empty()) {
    throw InputError("--from " + options.from_checkpoint + " starts a new run; a resumed run continues its own checkpoint");
  }
  if (!options.from_checkpoint.empty() && !std::filesystem::is_regular_file(options.from_checkpoint)) {
    throw InputError("--from " + options.from_checkpoint + ": no such checkpoint file");
  }
  if (options.resume && !options.overrides.empty()) {
    throw InputError("--set changes a new run's config; a resumed run keeps its own (" + folder.config_file +
                     "); start a new run from its checkpoint with --from");
  }
  TrainConfig config = LoadTrainConfig(options.resume ? folder.config_file : options.config_path, options.overrides);
  if (!options.method.empty()) {
    if (options.resume && options.method != config.method) {
      throw InputError("--method " + options.method + " differs from the run's method '" + config.method + "'");
    }
    config.method = options.method;
  }
  if (options.iterations > 0) config.iterations = options.iterations;
  if (options.seed >= 0) {
    if (options.resume && options.seed != config.seed) {
      throw InputError("--seed " + std::to_string(options.seed) + " differs from the run's seed " +
                       std::to_string(config.seed));
    }
    config.seed = options.seed;
  }
  if (options.threads > 0) config.num_threads = options.threads;
  ValidateTrainConfig(config, folder.config_file);
  const Communicator& comm = StartRun(folder, ToYamlString(config), options.resume, config.num_envs,
                                      config.num_threads, options.from_checkpoint);
  SkillDiscoveryTask task(config, comm);
  const std::string new_run =
      !options.from_checkpoint.empty()
          ? fmt::format("new {} run in {}", config.method, options.run_dir)
          : fmt::format("new {} run in {}: {} skills, {} envs x {} steps per iteration, {} iterations", config.method,
                        options.run_dir, config.num_skills, config.num_envs, config.steps_per_env, config.iterations);
  LearnSchedule schedule{config.iterations, config.checkpoint_every, config.keep_checkpoint_every, {}};
  if (config.keep_best) {
    // A judgement that fails (a damaged best.json, say) is reported and the training goes on.
    schedule.after_keep = [&](int iteration) {
      try {
        const nlohmann::json best = JudgeKeptCheckpoint(options.run_dir, iteration);
        spdlog::info("kept checkpoint {}: {} of 6 directions within the limits; best.json: {} of {} judged", iteration,
                     best.at("judged").back().at("bar").at("directions_within_limits").get<int>(),
                     best.at("iteration").get<int>(), best.at("judged").size());
      } catch (const std::exception& e) {
        spdlog::error("kept checkpoint {} was not judged: {}", iteration, e.what());
      }
    };
  }
  return Train(task, config.ppo, config.seed, comm, folder, options.resume, options.from_checkpoint, new_run,
               schedule, stop_requested);
}

int RunVelocityTraining(const VelocityRunOptions& options, const std::atomic<bool>& stop_requested) {
  const RunFolder folder = OpenRunFolder(options.run_dir, options.resume);
  if (options.resume && (!options.method.empty() || !options.library.empty() || !options.overrides.empty())) {
    throw InputError("--method, --library and --set set up a new run; a resumed run keeps its own (" +
                     folder.config_file + ")");
  }
  VelocityTrainConfig config = LoadVelocityTrainConfig(options.resume ? folder.config_file : options.config_path, options.overrides);
  if (!options.method.empty()) config.method = options.method;
  if (!options.library.empty()) config.library = options.library;
  if (options.iterations > 0) config.iterations = options.iterations;
  if (options.threads > 0) config.num_threads = options.threads;
  ValidateVelocityTrainConfig(config, folder.config_file);
  // A new selector runs its skills behind the target filter they were trained with.
  if (!options.resume && ParseVelocityMethod(config.method) == VelocityMethod::kSelector) {
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
    if (commands.skill_share > 0.0 && commands.skill_velocities.empty()) {
      const NearestSkillSelector dependable(library);
      for (const Eigen::Vector3d& v : dependable.velocities()) {
        commands.skill_velocities.insert(commands.skill_velocities.end(), {v.x(), v.y(), v.z()});
      }
    }
  }
  const Communicator& comm =
      StartRun(folder, ToYamlString(config), options.resume, config.num_envs, config.num_threads);
  VelocityTrackingTask task(config, comm);
  const std::string new_run = fmt::format(
      "new velocity-task run ({}{}) in {}: {} envs x {} steps per iteration, {} iterations", config.method,
      task.library() ? " over " + config.library : std::string(), options.run_dir, config.num_envs,
      config.steps_per_env, config.iterations);
  return Train(task, VelocityPpoConfig(config), config.seed, comm, folder, options.resume, "", new_run,
               {config.iterations, config.checkpoint_every, config.keep_checkpoint_every, {}}, stop_requested);
}

}  // namespace flsd
