// flsd train and flsd train-selector.

#include <csignal>
#include <memory>

#include "core/check.h"
#include "skills/learning/tasks/velocity_tracking_task.h"
#include "skills/learning/runners/training_run.h"
#include "tools/flsd/subcommands.h"

namespace flsd::cli {
namespace {

std::atomic<bool> g_stop{false};
void RequestStop(int) { g_stop = true; }

}  // namespace

void StopOnSignals() {
  std::signal(SIGINT, RequestStop);
  std::signal(SIGTERM, RequestStop);
}

const std::atomic<bool>& StopRequested() { return g_stop; }

void AddTraining(CLI::App& app, Subcommands& out) {
  auto train = std::make_shared<TrainingRunOptions>();
  CLI::App* train_cmd = app.add_subcommand("train", "Train skills with FLSD (Algorithm 1) or the DIAYN baseline");
  train_cmd->add_option("--config", train->config_path, "Training config (configs/*.yaml)");
  train_cmd->add_option("--method", train->method, "flsd or diayn (default: the config's)")
      ->check(CLI::IsMember({"flsd", "diayn"}));
  train_cmd->add_option("--out", train->run_dir, "Run folder (config.yaml, checkpoint.pt, progress.csv)")->required();
  train_cmd->add_flag("--resume", train->resume, "Continue the run in --out from its checkpoint");
  train_cmd->add_option("--from", train->from_checkpoint,
                        "Start a new run from this checkpoint (fine-tuning with --config's settings)");
  train_cmd->add_option("--iterations", train->iterations, "Train until this many iterations in total")
      ->check(CLI::Range(1, 100000000));
  train_cmd->add_option("--seed", train->seed, "Seed of a new run (default: the config's)")->check(CLI::Range(0, 1 << 30));
  train_cmd->add_option("--threads", train->threads, "Simulation threads per process (default: the config's)")
      ->check(CLI::Range(1, 1024));
  train_cmd->add_option("--set", train->overrides, "Change a new run's config: key.path=value (repeatable)");
  out.push_back({train_cmd, [train] {
                   if (!train->resume && train->config_path.empty()) {
                     throw InputError("train: --config is required for a new run");
                   }
                   StopOnSignals();
                   return RunTraining(*train, StopRequested());
                 }});

  auto task = std::make_shared<VelocityRunOptions>();
  CLI::App* task_cmd = app.add_subcommand(
      "train-selector", "Train the velocity-tracking skill selector (or, --method scratch, a policy from scratch)");
  task_cmd->add_option("--config", task->config_path, "Task training config (configs/selector_*.yaml)");
  task_cmd->add_option("--method", task->method, "selector or scratch (default: the config's)")
      ->check(CLI::IsMember({"selector", "scratch"}));
  task_cmd->add_option("--library", task->library, "Skill library the selector chooses from (default: the config's)");
  task_cmd->add_option("--out", task->run_dir, "Run folder (config.yaml, checkpoint.pt, progress.csv)")->required();
  task_cmd->add_flag("--resume", task->resume, "Continue the run in --out from its checkpoint");
  task_cmd->add_option("--iterations", task->iterations, "Train until this many iterations in total")
      ->check(CLI::Range(1, 100000000));
  task_cmd->add_option("--threads", task->threads, "Simulation threads (default: the config's)")->check(CLI::Range(1, 1024));
  task_cmd->add_option("--set", task->overrides, "Change a new run's config: key.path=value (repeatable)");
  out.push_back({task_cmd, [task] {
                   if (!task->resume && task->config_path.empty()) {
                     throw InputError("train-selector: --config is required for a new run");
                   }
                   StopOnSignals();
                   return RunVelocityTraining(*task, StopRequested());
                 }});
}

}  // namespace flsd::cli
