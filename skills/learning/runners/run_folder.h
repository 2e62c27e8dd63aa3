#pragma once
// A training run's folder: config.yaml (the resolved config), commits (the build of each sitting),
// checkpoint.pt (the latest), checkpoints/ITER.pt (the kept ones) and progress.csv.

#include <optional>
#include <string>
#include <vector>

namespace flsd {

struct RunFolder {
  std::string dir, config_file, checkpoint, progress;
};

// The paths of run_dir; throws InputError if resuming finds no checkpoint, or starting finds one.
RunFolder OpenRunFolder(const std::string& run_dir, bool resume);

// `text` as an iteration number (1 to 9 digits, nothing else), or nothing.
std::optional<int> ParseIteration(const std::string& text);
// run_dir/checkpoints/ITER.pt, where OnPolicyRunner::Learn keeps a copy of the checkpoint every
// `keep_every` iterations.
std::string KeptCheckpointPath(const std::string& run_dir, int iteration);
// The iterations whose checkpoints the run kept, in order.
std::vector<int> KeptIterations(const std::string& run_dir);
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

}  // namespace flsd
