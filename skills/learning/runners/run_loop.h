#pragma once
// What every training command shares: the run folder (config.yaml, commits, checkpoint.pt,
// progress.csv) and the loop that iterates, logs, checkpoints, and stops cleanly on request or
// when a loss turns non-finite.

#include <spdlog/spdlog.h>

#include <atomic>
#include <optional>
#include <string>

#include "skills/learning/runners/communicator.h"
#include "skills/learning/runners/progress_log.h"

namespace flsd {

struct RunFolder {
  std::string dir, config_file, checkpoint, progress;
};

// The paths of run_dir; throws InputError if resuming finds no checkpoint, or starting finds one.
RunFolder OpenRunFolder(const std::string& run_dir, bool resume);

// `text` as an iteration number (1 to 9 digits, nothing else), or nothing.
std::optional<int> ParseIteration(const std::string& text);
// run_dir/checkpoints/ITER.pt, where RunIterations keeps a copy of the checkpoint every
// `keep_every` iterations.
std::string KeptCheckpointPath(const std::string& run_dir, int iteration);
// The checkpoint a command loads: the latest (iteration 0) or a kept one. Throws InputError
// naming the iterations kept when there is none for `iteration`.
std::string RunCheckpoint(const std::string& run_dir, int iteration);
// Copies the checkpoint just saved to its kept place, atomically.
void KeepCheckpoint(const RunFolder& folder, int iteration);

// Creates the folder, writes the resolved config atomically, and appends the build's commit to
// the commits file (each sitting of a run adds one line; a run started from another run's
// checkpoint names it).
void RecordRunStart(const RunFolder& folder, const std::string& config_yaml, bool resume,
                    const std::string& from_checkpoint = "");

// Runs trainer.RunIteration() until `iterations` or a stop request, appending `row(stats)` to
// progress.csv and `line(stats, eta_seconds)` to the log, and checkpointing every
// `checkpoint_every` iterations and at the end, keeping a copy every `keep_every` iterations (0:
// none). Returns 0, or 3 when stats.finite turned false
// (the last good checkpoint is kept as it was). With several ranks in `comm`, every rank iterates
// and only the leader writes; a stop requested on any rank stops them all after the same iteration.
template <class Trainer, class Row, class Line>
int RunIterations(Trainer& trainer, const Communicator& comm, const RunFolder& folder, const std::string& header,
                  int iterations, int checkpoint_every, int keep_every, const std::atomic<bool>& stop_requested,
                  Row row, Line line) {
  std::optional<ProgressLog> log;
  if (comm.leader()) log.emplace(folder.progress, header, trainer.iteration());
  double seconds_per_iteration = 0.0;
  int saved_iteration = trainer.iteration();
  bool stopped = false;
  while (trainer.iteration() < iterations && !(stopped = comm.Any(stop_requested))) {
    const auto stats = trainer.RunIteration();
    if (!stats.finite) {
      spdlog::error("iteration {}: a loss became NaN or infinite; stopping. {} is kept as it was at iteration {}",
                    stats.iteration, folder.checkpoint, saved_iteration);
      return 3;
    }
    if (!comm.leader()) continue;
    log->Append(row(stats));
    seconds_per_iteration = seconds_per_iteration == 0.0 ? stats.seconds_total
                                                         : 0.9 * seconds_per_iteration + 0.1 * stats.seconds_total;
    spdlog::info("{}", line(stats, seconds_per_iteration * (iterations - stats.iteration)));
    const bool keep = keep_every > 0 && stats.iteration % keep_every == 0;
    if (stats.iteration % checkpoint_every == 0 || keep) {
      trainer.SaveCheckpoint(folder.checkpoint);
      saved_iteration = stats.iteration;
    }
    if (keep) KeepCheckpoint(folder, stats.iteration);
  }
  if (!comm.leader()) return 0;
  if (saved_iteration != trainer.iteration()) trainer.SaveCheckpoint(folder.checkpoint);
  spdlog::info("{} at iteration {}; checkpoint {}", stopped ? "stopped" : "finished", trainer.iteration(),
               folder.checkpoint);
  return 0;
}

}  // namespace flsd
