#pragma once
// The paper's skill figures (Figs. 4-6) and the numbers behind them, from evaluation rollouts.
// Plain C++: the rollouts come from `flsd eval`'s EvaluateSkills.

#include <string>
#include <vector>

#include "report/svg_plot.h"
#include "skills/learning/evaluation/metrics.h"

namespace flsd {

// Fig. 5: the distribution over trajectory segments of one joint's velocity spectrum, in dB
// referenced to 1 (rad/s)^2/Hz. Each skill that survives (Survives) is
// cut into whole segments of `segment` samples, and each segment's periodogram (PowerSpectrum) is
// one sample of the distribution at every frequency.
struct PsdBands {
  std::vector<double> frequency;  // Hz, 0 .. rate/2 in steps of rate/segment
  std::vector<double> p5, q1, median, q3, p95;
  int segments = 0;
};
PsdBands JointVelocityPsdBands(const std::vector<SkillTrajectory>& skills, int joint, double rate_hz,
                               int segment);

// The value below which `fraction` of `values` lie (linear interpolation between order statistics).
double Percentile(std::vector<double> values, double fraction);

// Fig. 6: states of several evaluations projected onto the first two principal components of them
// all together. A state is the coverage dimensions (normalised, NormalizedCoverageState) and the
// joint angles, each standardised over all the states; every `stride`-th step of each skill is used.
struct Embedding {
  std::vector<double> x, y;
  std::vector<int> evaluation, skill;  // where each point came from
  double explained = 0.0;              // fraction of the variance the two components hold
};
Embedding PrincipalComponentEmbedding(const std::vector<const Evaluation*>& evaluations, int stride);

// A colour per evaluation (hue) and skill (shade), as the paper's Fig. 6.
std::string SkillColor(int evaluation, int skill, int num_skills);

// Fig. 4: per skill, the range (bar) and mean (dot) of each normalised coverage dimension, one colour
// per dimension; skills that did not survive 500 steps are drawn dashed (coverage does not count them).
SvgPlot CoverageFigure(const Evaluation& evaluation, const std::string& title);
// Fig. 5's chart: the 5-95 % band shaded, the quartiles dashed, the median solid.
SvgPlot PsdFigure(const PsdBands& bands, const std::string& title, double y_lo, double y_hi);
SvgPlot EmbeddingFigure(const Embedding& embedding, const std::vector<std::string>& labels, int num_skills);
// Mean velocity of every skill that survived 500 steps, one colour per evaluation: x against
// (axis 1) lateral velocity or (axis 2) yaw rate, with the direction bar's thresholds (0.3 m/s,
// 0.5 rad/s).
SvgPlot MeanVelocityFigure(const std::vector<const Evaluation*>& evaluations, const std::vector<std::string>& labels,
                           int axis);

}  // namespace flsd
