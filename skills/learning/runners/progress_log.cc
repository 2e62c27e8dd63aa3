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

}  // namespace flsd
