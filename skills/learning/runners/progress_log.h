#pragma once
#include <fstream>
#include <string>


namespace flsd {

// A run's progress.csv: a header, then one row per iteration, each starting with the iteration.
class ProgressLog {
 public:
  // Opens (or creates) the file. Rows past `keep_through_iteration`, written by a run that went on
  // after its last checkpoint, are dropped so that a resumed run does not repeat them.
  ProgressLog(const std::string& path, const std::string& header, int keep_through_iteration);
  void Append(const std::string& row);  // without the newline

 private:
  std::string path_;
  std::ofstream out_;
};

// One progress.csv row as a list of named columns, so that the header and the row come from the
// same list: Add("fall_fraction", stats.fall_fraction, "%.4f").
class ProgressRecord {
 public:
  ProgressRecord& Add(const char* column, double value, const char* format);
  ProgressRecord& Add(const char* column, long value);
  const std::string& header() const { return header_; }
  const std::string& row() const { return row_; }

 private:
  void Column(const char* column, const char* text);
  std::string header_, row_;
};

// "1h02m" or "3m05s".
std::string Duration(double seconds);

}  // namespace flsd
