#pragma once
// `flsd report`: the paper's comparison (Table I, Table II, Figs. 4-6, learning curves) of skill
// runs, as an HTML page with SVG figures and a JSON file of the same numbers. Plain C++: the caller
// rolls the skills out (EvaluateSkills) and hands the evaluations in.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "skills/learning/evaluation/metrics.h"

namespace flsd {

struct ReportRun {
  std::string label;   // the run folder's name
  std::string method;  // flsd or diayn
  int seed = 0;
  int iteration = 0;
  long env_steps = 0;
  std::string progress_csv;  // learning curves; empty: none
  Evaluation nominal;        // no randomisation (the paper's evaluation)
  Evaluation randomized;     // the training randomisation on
};

// How many skills move each way the direction bar names, among those that survive 500 steps:
// forward / backward (v_x >= / <= +-0.3 m/s), sideways (|v_y| >= 0.3 m/s), turning (|w_z| >= 0.5 rad/s).
struct DirectionCounts {
  int forward = 0, backward = 0, sideways = 0, turning = 0;
};
inline constexpr double kMovingSpeed = 0.3;     // m/s
inline constexpr double kTurningRate = 0.5;     // rad/s
DirectionCounts CountDirections(const Evaluation& evaluation);

// Skills that survive 500 steps both without and with the training randomisation.
int RobustSurvivors(const ReportRun& run);

// Every number of the report: per run, per method (mean over its runs), and FLSD against DIAYN.
nlohmann::json ReportJson(const std::vector<ReportRun>& runs);

// Writes dir/index.html, dir/report.json and the figures (dir/*.svg). `commit` is printed on the page.
void WriteSkillReport(const std::vector<ReportRun>& runs, const std::string& dir, const std::string& commit);

}  // namespace flsd
