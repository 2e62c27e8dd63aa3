#pragma once
#include <string>
#include <vector>

namespace flsd {

struct ReportOptions {
  std::vector<std::string> runs;  // skill run folders (flsd train)
  std::string output;             // folder for index.html, report.json and the figures
  int steps = 0;                  // per skill; 0: each run's episode length
};

// Rolls every skill of every run out (as flsd eval does, without and with the training
// randomisation) and writes the report (report/skill_report.h). Returns 0.
int RunReport(const ReportOptions& options);

}  // namespace flsd
