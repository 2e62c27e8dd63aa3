#pragma once
#include <fstream>
#include <string>

#include "skills/learning/trainer.h"

namespace flsd {

// The run's progress.csv: one row of IterationStats per iteration.
class ProgressLog {
 public:
  // Opens (or creates) the file. Rows past `keep_through_iteration`, written by a run that went on
  // after its last checkpoint, are dropped so that a resumed run does not repeat them.
  ProgressLog(const std::string& path, int keep_through_iteration);
  void Append(const IterationStats& stats);

 private:
  std::string path_;
  std::ofstream out_;
};

// One line for the terminal: iteration, speed, ETA, episode length, discriminator accuracy, reward.
std::string ProgressLine(const IterationStats& stats, int total_iterations, int num_skills, double eta_seconds);

}  // namespace flsd
