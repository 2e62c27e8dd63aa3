#include "skills/learning/training_run.h"

#include <dlfcn.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "core/atomic_file.h"
#include "core/check.h"
#include "core/thread_pool.h"
#include "flsd_commit.h"
#include "skills/learning/progress_log.h"
#include "skills/learning/trainer.h"

namespace flsd {

void ConfigureTorchThreads(int threads) {
  using SetThreads = void (*)(int);
  if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set(1);
  torch::set_num_threads(ResolveThreadCount(threads));
}

int RunTraining(const TrainingRunOptions& options, const std::atomic<bool>& stop_requested) {
  namespace fs = std::filesystem;
  const std::string config_file = (fs::path(options.run_dir) / "config.yaml").string();
  const std::string checkpoint = (fs::path(options.run_dir) / "checkpoint.pt").string();

  TrainConfig config;
  if (options.resume) {
    if (!fs::exists(checkpoint)) {
      throw InputError(options.run_dir + ": nothing to resume (no checkpoint.pt)");
    }
    config = LoadTrainConfig(config_file);
  } else {
    if (fs::exists(checkpoint)) {
      throw InputError(options.run_dir + " already holds a run (checkpoint.pt): pass --resume to continue it, "
                       "or choose another --out");
    }
    config = LoadTrainConfig(options.config_path);
  }
  if (!options.method.empty()) {
    if (options.resume && options.method != config.method) {
      throw InputError("--method " + options.method + " differs from the run's method '" + config.method + "'");
    }
    config.method = options.method;
  }
  if (options.iterations > 0) config.iterations = options.iterations;
  ValidateTrainConfig(config, config_file);
  fs::create_directories(options.run_dir);
  WriteFileAtomically(config_file, ToYamlString(config) + "\n");
  ConfigureTorchThreads(config.num_threads);
  // Each sitting of the run appends the commit it was built from.
  {
    std::ofstream commits((fs::path(options.run_dir) / "commits").string(), std::ios::app);
    commits << FLSD_GIT_COMMIT << (options.resume ? " (resumed)" : "") << "\n";
  }

  Trainer trainer(config);
  if (options.resume) {
    trainer.LoadCheckpoint(checkpoint);
    spdlog::info("resumed {} at iteration {} ({} env steps)", options.run_dir, trainer.iteration(), trainer.env_steps());
  } else {
    spdlog::info("new {} run in {}: {} skills, {} envs x {} steps per iteration, {} iterations",
                 config.method, options.run_dir, config.num_skills, config.num_envs, config.steps_per_env,
                 config.iterations);
  }
  ProgressLog log((fs::path(options.run_dir) / "progress.csv").string(), trainer.iteration());

  double seconds_per_iteration = 0.0;
  int saved_iteration = trainer.iteration();
  while (trainer.iteration() < config.iterations && !stop_requested) {
    const IterationStats stats = trainer.RunIteration();
    if (!stats.finite) {
      spdlog::error("iteration {}: a loss became NaN or infinite (ppo {}, pae {}, discriminator {}); stopping. "
                    "{} is kept as it was at iteration {}",
                    stats.iteration, stats.ppo.finite ? "finite" : "non-finite", stats.pae_loss,
                    stats.discriminator_loss, checkpoint, saved_iteration);
      return 3;
    }
    log.Append(stats);
    seconds_per_iteration = seconds_per_iteration == 0.0 ? stats.seconds_total
                                                         : 0.9 * seconds_per_iteration + 0.1 * stats.seconds_total;
    spdlog::info("{}", ProgressLine(stats, config.iterations, config.num_skills,
                                    seconds_per_iteration * (config.iterations - stats.iteration)));
    if (stats.iteration % config.checkpoint_every == 0) {
      trainer.SaveCheckpoint(checkpoint);
      saved_iteration = stats.iteration;
    }
  }
  if (saved_iteration != trainer.iteration()) trainer.SaveCheckpoint(checkpoint);
  spdlog::info("{} at iteration {}; checkpoint {}", stop_requested ? "stopped" : "finished", trainer.iteration(),
               checkpoint);
  return 0;
}

}  // namespace flsd
