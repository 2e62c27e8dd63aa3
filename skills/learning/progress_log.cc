#include "skills/learning/progress_log.h"

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <vector>

#include "core/atomic_file.h"
#include "core/check.h"

namespace flsd {
std::string SkillProgressHeader() {
  std::string header =
    "iteration,env_steps,steps_per_s,episodes_ended,mean_episode_length,fall_fraction,"
    "discriminator_accuracy,intrinsic_reward,discriminator_loss,pae_loss,surrogate_loss,value_loss,"
    "entropy,kl,learning_rate,action_std,seconds_physics,seconds_policy,seconds_bookkeeping,"
    "seconds_reward,seconds_ppo,seconds_pae,seconds_discriminator,seconds_total,regularization,"
    "termination_probability";
  for (const char* name : kConstraintNames) header += std::string(",violation_") + name;
  return header;
}

std::string Duration(double seconds) {
  char text[32];
  const long s = static_cast<long>(seconds);
  if (s >= 3600) {
    std::snprintf(text, sizeof(text), "%ldh%02ldm", s / 3600, (s % 3600) / 60);
  } else {
    std::snprintf(text, sizeof(text), "%ldm%02lds", s / 60, s % 60);
  }
  return text;
}

ProgressLog::ProgressLog(const std::string& path, const std::string& header, int keep_through_iteration)
    : path_(path) {
  std::vector<std::string> kept;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line.rfind("iteration,", 0) == 0) continue;  // the header
    if (std::stoi(line.substr(0, line.find(','))) <= keep_through_iteration) kept.push_back(line);
  }
  std::string contents = header + "\n";
  for (const std::string& line : kept) contents += line + "\n";
  WriteFileAtomically(path, contents);
  out_.open(path, std::ios::app);
  if (!out_) throw InputError(path + ": cannot open for writing");
}

void ProgressLog::Append(const std::string& row) {
  out_ << row << '\n';
  out_.flush();
}

std::string ProgressRow(const IterationStats& s) {
  char row[1024];
  std::snprintf(row, sizeof(row),
                "%d,%ld,%.1f,%d,%.2f,%.4f,%.5f,%.5f,%.5f,%.6f,%.6f,%.6f,%.5f,%.6f,%.3g,%.5f,"
                "%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.6f",
                s.iteration, s.env_steps, s.steps_per_s, s.episodes_ended, s.mean_episode_length,
                s.fall_fraction, s.discriminator_accuracy, s.intrinsic_reward, s.discriminator_loss,
                s.pae_loss, s.ppo.surrogate_loss, s.ppo.value_loss, s.ppo.entropy, s.ppo.kl,
                s.ppo.learning_rate, s.action_std, s.seconds_physics, s.seconds_policy,
                s.seconds_bookkeeping, s.seconds_reward, s.seconds_ppo, s.seconds_pae,
                s.seconds_discriminator, s.seconds_total, s.regularization);
  std::string out = row;
  char number[32];
  std::snprintf(number, sizeof(number), ",%.5f", s.constraints.mean_probability);
  out += number;
  for (double rate : s.constraints.violation_rate) {
    std::snprintf(number, sizeof(number), ",%.5f", rate);
    out += number;
  }
  return out;
}

std::string ProgressLine(const IterationStats& s, int total_iterations, int num_skills, double eta_seconds) {
  char line[512];
  std::snprintf(line, sizeof(line),
                "it %d/%d | %.0f steps/s | ETA %s | ep len %.0f (falls %.0f%%) | disc acc %.3f "
                "(chance %.3f) | r_int %.3f | penalty %.4f | pae %.4f | lr %.1e | std %.3f",
                s.iteration, total_iterations, s.steps_per_s, Duration(eta_seconds).c_str(),
                s.mean_episode_length, 100.0 * s.fall_fraction, s.discriminator_accuracy,
                1.0 / num_skills, s.intrinsic_reward, s.regularization, s.pae_loss, s.ppo.learning_rate, s.action_std);
  return line;
}

}  // namespace flsd
