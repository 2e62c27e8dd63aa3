#include "skills/learning/runners/training_run.h"

#include <dlfcn.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "core/atomic_file.h"
#include "core/check.h"
#include "core/thread_pool.h"
#include "flsd_commit.h"
#include "skills/learning/runners/policy_learner.h"
#include "skills/learning/runners/run_loop.h"
#include "skills/learning/runners/trainer.h"

namespace flsd {

void ConfigureTorchThreads(int threads) {
  using SetThreads = void (*)(int);
  if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set(1);
  torch::set_num_threads(ResolveThreadCount(threads));
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

RunFolder OpenRunFolder(const std::string& run_dir, bool resume) {
  namespace fs = std::filesystem;
  RunFolder folder{run_dir, (fs::path(run_dir) / "config.yaml").string(), (fs::path(run_dir) / "checkpoint.pt").string(),
                   (fs::path(run_dir) / "progress.csv").string()};
  if (resume && !fs::exists(folder.checkpoint)) {
    throw InputError(run_dir + ": nothing to resume (no checkpoint.pt)");
  }
  if (!resume && fs::exists(folder.checkpoint)) {
    throw InputError(run_dir + " already holds a run (checkpoint.pt): pass --resume to continue it, "
                     "or choose another --out");
  }
  return folder;
}

std::optional<int> ParseIteration(const std::string& text) {
  if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos) return {};
  return std::stoi(text);
}

std::string KeptCheckpointPath(const std::string& run_dir, int iteration) {
  return (std::filesystem::path(run_dir) / "checkpoints" / (std::to_string(iteration) + ".pt")).string();
}

std::string RunCheckpoint(const std::string& run_dir, int iteration) {
  namespace fs = std::filesystem;
  if (iteration == 0) return (fs::path(run_dir) / "checkpoint.pt").string();
  const std::string path = KeptCheckpointPath(run_dir, iteration);
  if (fs::exists(path)) return path;
  std::vector<int> kept;
  const fs::path dir = fs::path(run_dir) / "checkpoints";
  if (fs::is_directory(dir)) {
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::optional<int> kept_iteration = ParseIteration(entry.path().stem().string());
      if (entry.path().extension() == ".pt" && kept_iteration) kept.push_back(*kept_iteration);
    }
  }
  std::sort(kept.begin(), kept.end());
  std::string list;
  for (int k : kept) list += (list.empty() ? "" : ", ") + std::to_string(k);
  throw InputError(run_dir + " kept no checkpoint of iteration " + std::to_string(iteration) + " (" +
                   (kept.empty() ? std::string("it kept none") : "kept: " + list) + ")");
}

void KeepCheckpoint(const RunFolder& folder, int iteration) {
  namespace fs = std::filesystem;
  const std::string path = KeptCheckpointPath(folder.dir, iteration);
  fs::create_directories(fs::path(path).parent_path());
  WriteFileAtomically(path, [&](const std::string& temp_path) {
    fs::copy_file(folder.checkpoint, temp_path, fs::copy_options::overwrite_existing);
  });
}

void RecordRunStart(const RunFolder& folder, const std::string& config_yaml, bool resume,
                    const std::string& from_checkpoint) {
  namespace fs = std::filesystem;
  fs::create_directories(folder.dir);
  WriteFileAtomically(folder.config_file, config_yaml + "\n");
  std::ofstream commits((fs::path(folder.dir) / "commits").string(), std::ios::app);
  commits << FLSD_GIT_COMMIT << (resume ? " (resumed)" : "")
          << (from_checkpoint.empty() ? "" : " (from " + from_checkpoint + ")") << "\n";
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
  ConfigureTorchThreads(threads);
  if (comm.size() == 1) {
    WarnIfOversubscribed(threads);
  } else {
    spdlog::info("{} ranks, {} envs and {} threads each", comm.size(), local_envs, threads);
  }
  return comm;
}

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
  Trainer trainer(config, comm);
  if (options.resume) {
    trainer.LoadCheckpoint(folder.checkpoint);
    spdlog::info("resumed {} at iteration {} ({} env steps)", options.run_dir, trainer.iteration(), trainer.env_steps());
  } else if (!options.from_checkpoint.empty()) {
    trainer.LoadCheckpoint(options.from_checkpoint);
    spdlog::info("new {} run in {} from {} at iteration {} ({} env steps)", config.method, options.run_dir,
                 options.from_checkpoint, trainer.iteration(), trainer.env_steps());
  } else {
    spdlog::info("new {} run in {}: {} skills, {} envs x {} steps per iteration, {} iterations",
                 config.method, options.run_dir, config.num_skills, config.num_envs, config.steps_per_env,
                 config.iterations);
  }
  return RunIterations(
      trainer, comm, folder, SkillProgress(IterationStats{}).header(), config.iterations, config.checkpoint_every,
      config.keep_checkpoint_every, stop_requested,
      [](const IterationStats& s) { return SkillProgress(s).row(); },
      [&](const IterationStats& s, double eta) { return ProgressLine(s, config.iterations, config.num_skills, eta); });
}

}  // namespace flsd
