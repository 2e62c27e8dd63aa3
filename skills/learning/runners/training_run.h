#pragma once
// The training commands' runs: a run folder, the job's ranks, one task and the on-policy runner
// that trains it.

#include <atomic>
#include <string>
#include <vector>

#include "skills/learning/runners/communicator.h"
#include "skills/learning/runners/run_folder.h"

namespace flsd {

struct TrainingRunOptions {
  std::string config_path;  // a new run's config; ignored on resume (the run keeps its own)
  std::string method;       // "flsd" or "diayn"; empty: the config's
  std::string run_dir;
  bool resume = false;
  // A new run's starting point: another run's checkpoint (networks, optimisers, normaliser,
  // iteration and step counts), trained on with this run's config. Empty: from scratch.
  std::string from_checkpoint;
  int iterations = 0;  // > 0: train until this many iterations in total
  int seed = -1;       // >= 0: a new run's seed instead of the config's (another seed, same config)
  int threads = 0;     // > 0: simulation threads (per rank) instead of the config's
  std::vector<std::string> overrides;  // a new run's "key.path=value" changes to its config
};

// Trains in run_dir: config.yaml (the resolved config), checkpoint.pt (every checkpoint_every
// iterations and at exit, including on a stop request), progress.csv. Returns 0 when the run
// reached its iterations or was stopped, 3 when a loss turned non-finite (the last good checkpoint
// is kept, nothing is written over it). Runs alone, or as one rank of the MPI job it was launched
// in (Communicator::World()): each rank steps its share of config.num_envs, the leader alone writes.
int RunTraining(const TrainingRunOptions& options, const std::atomic<bool>& stop_requested);

struct VelocityRunOptions {
  std::string config_path;  // a new run's config; ignored on resume
  std::string method;       // overrides the config's, new runs only
  std::string library;      // overrides the config's, new runs only
  std::string run_dir;
  bool resume = false;
  int iterations = 0;
  int threads = 0;  // overrides the config's num_threads
  std::vector<std::string> overrides;  // a new run's "key.path=value" changes to its config
};
// As RunTraining, for the velocity-tracking task (a skill selector, or a policy from scratch).
int RunVelocityTraining(const VelocityRunOptions& options, const std::atomic<bool>& stop_requested);

// Joins the job's ranks (Communicator::World(): the mpirun job, or this process alone) and starts
// a run in `folder`: the leader records it (RecordRunStart), the other ranks leave the talking to
// it, and libtorch gets `threads` threads. Throws InputError unless `num_envs` divides among the
// ranks.
const Communicator& StartRun(const RunFolder& folder, const std::string& config_yaml, bool resume, int num_envs,
                             int threads, const std::string& from_checkpoint = "");

// Sets up a process that trains or evaluates networks. Limits BLAS to one thread: libtorch
// parallelises its own kernels, and OpenBLAS's own pool on top of it oversubscribes the cores
// (measured: a 4096-sample MLP update 15x slower). Keeps freed memory in the heap for reuse rather
// than returning it to the kernel (measured: the paper config's iteration 191 s against 106 s).
void ConfigureLearningProcess(int threads);

// Logs a warning when `threads` (more than one) and the 1-minute load average together exceed the
// machine's cores: two training processes of 2 threads each on 2 cores were
// measured 6x slower per iteration than one alone, as libtorch's threads wait on each other.
void WarnIfOversubscribed(int threads);

}  // namespace flsd
