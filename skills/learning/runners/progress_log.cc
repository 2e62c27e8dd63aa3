#include "skills/learning/runners/progress_log.h"

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <vector>

#include "core/atomic_file.h"
#include "core/check.h"

namespace flsd {
ProgressRecord& ProgressRecord::Add(const char* column, double value, const char* format) {
  char text[400];  // "%.6f" of the largest double takes 316 characters: a huge loss is written whole
  std::snprintf(text, sizeof(text), format, value);
  Column(column, text);
  return *this;
}

ProgressRecord& ProgressRecord::Add(const char* column, long value) {
  Column(column, std::to_string(value).c_str());
  return *this;
}

void ProgressRecord::Column(const char* column, const char* text) {
  if (!header_.empty()) {
    header_ += ',';
    row_ += ',';
  }
  header_ += column;
  row_ += text;
}

ProgressRecord SkillProgress(const IterationStats& s) {
  ProgressRecord r;
  r.Add("iteration", long{s.iteration})
      .Add("env_steps", s.env_steps)
      .Add("steps_per_s", s.steps_per_s, "%.1f")
      .Add("episodes_ended", long{s.episodes_ended})
      .Add("mean_episode_length", s.mean_episode_length, "%.2f")
      .Add("fall_fraction", s.fall_fraction, "%.4f")
      .Add("discriminator_accuracy", s.discriminator_accuracy, "%.5f")
      .Add("intrinsic_reward", s.intrinsic_reward, "%.5f")
      .Add("discriminator_loss", s.discriminator_loss, "%.5f")
      .Add("pae_loss", s.pae_loss, "%.6f")
      .Add("surrogate_loss", s.ppo.surrogate_loss, "%.6f")
      .Add("value_loss", s.ppo.value_loss, "%.6f")
      .Add("entropy", s.ppo.entropy, "%.5f")
      .Add("kl", s.ppo.kl, "%.6f")
      .Add("learning_rate", s.ppo.learning_rate, "%.3g")
      .Add("action_std", s.action_std, "%.5f")
      .Add("seconds_physics", s.seconds_physics, "%.4f")
      .Add("seconds_policy", s.seconds_policy, "%.4f")
      .Add("seconds_bookkeeping", s.seconds_bookkeeping, "%.4f")
      .Add("seconds_reward", s.seconds_reward, "%.4f")
      .Add("seconds_ppo", s.seconds_ppo, "%.4f")
      .Add("seconds_pae", s.seconds_pae, "%.4f")
      .Add("seconds_discriminator", s.seconds_discriminator, "%.4f")
      .Add("seconds_total", s.seconds_total, "%.4f")
      .Add("regularization", s.regularization, "%.6f")
      .Add("termination_probability", s.constraints.mean_probability, "%.5f");
  for (size_t c = 0; c < kConstraintNames.size(); ++c) {
    const std::string column = std::string("violation_") + kConstraintNames[c];
    r.Add(column.c_str(), s.constraints.violation_rate[c], "%.5f");
  }
  return r;
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
