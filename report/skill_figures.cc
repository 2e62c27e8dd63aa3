#include "report/skill_figures.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace flsd {
namespace {

constexpr double kTinyPower = 1e-10;  // floor before the logarithm: -100 dB, below any moving joint

bool Counted(const SkillTrajectory& s) { return Survives(static_cast<int>(s.points.size())); }

const char* const kRunColors[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
const int kRunHues[] = {0, 210, 120, 280, 30, 330};

}  // namespace

double Percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return NAN;
  std::sort(values.begin(), values.end());
  const double position = std::clamp(fraction, 0.0, 1.0) * (values.size() - 1);
  const size_t below = static_cast<size_t>(std::floor(position));
  const size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (position - below) * (values[above] - values[below]);
}

PsdBands JointVelocityPsdBands(const std::vector<SkillTrajectory>& skills, int joint, double rate_hz, int segment) {
  PsdBands bands;
  const int bins = segment / 2 + 1;
  std::vector<std::vector<double>> by_bin(bins);
  for (const SkillTrajectory& s : skills) {
    if (!Counted(s)) continue;
    for (size_t start = 0; start + segment <= s.points.size(); start += segment) {
      std::vector<double> x(segment);
      for (int t = 0; t < segment; ++t) x[t] = s.points[start + t].joint_velocity[joint];
      const std::vector<double> psd = PowerSpectrum(x, rate_hz);
      for (int j = 0; j < bins; ++j) by_bin[j].push_back(10.0 * std::log10(std::max(psd[j], kTinyPower)));
      ++bands.segments;
    }
  }
  if (bands.segments == 0) return bands;
  for (int j = 0; j < bins; ++j) {
    bands.frequency.push_back(j * rate_hz / segment);
    bands.p5.push_back(Percentile(by_bin[j], 0.05));
    bands.q1.push_back(Percentile(by_bin[j], 0.25));
    bands.median.push_back(Percentile(by_bin[j], 0.50));
    bands.q3.push_back(Percentile(by_bin[j], 0.75));
    bands.p95.push_back(Percentile(by_bin[j], 0.95));
  }
  return bands;
}

Embedding PrincipalComponentEmbedding(const std::vector<const Evaluation*>& evaluations, int stride) {
  constexpr int kFeatures = kCoverageDims + a1::kNumJoints;
  std::vector<Eigen::Matrix<double, kFeatures, 1>> states;
  Embedding embedding;
  for (size_t e = 0; e < evaluations.size(); ++e) {
    for (const SkillTrajectory& s : evaluations[e]->trajectories) {
      for (size_t t = 0; t < s.points.size(); t += std::max(1, stride)) {
        Eigen::Matrix<double, kFeatures, 1> x;
        const auto coverage = NormalizedCoverageState(s.points[t]);
        for (int d = 0; d < kCoverageDims; ++d) x[d] = coverage[d];
        for (int j = 0; j < a1::kNumJoints; ++j) x[kCoverageDims + j] = s.points[t].joint_position[j];
        states.push_back(x);
        embedding.evaluation.push_back(static_cast<int>(e));
        embedding.skill.push_back(s.skill);
      }
    }
  }
  if (states.size() < 2) return {};
  Eigen::Matrix<double, Eigen::Dynamic, kFeatures> data(states.size(), kFeatures);
  for (size_t i = 0; i < states.size(); ++i) data.row(i) = states[i].transpose();
  data.rowwise() -= data.colwise().mean();
  // Standardise, so metres, rad/s and radians weigh alike; a constant feature stays zero.
  const Eigen::Matrix<double, 1, kFeatures> scale =
      (data.colwise().squaredNorm() / double(states.size() - 1)).cwiseSqrt().cwiseMax(1e-9);
  data.array().rowwise() /= scale.array();
  const Eigen::Matrix<double, kFeatures, kFeatures> covariance = data.transpose() * data / double(states.size() - 1);
  // Eigenvalues come in increasing order: the last two columns are the principal axes.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, kFeatures, kFeatures>> solver(covariance);
  const Eigen::Matrix<double, Eigen::Dynamic, 2> projected = data * solver.eigenvectors().rightCols<2>();
  embedding.x.resize(states.size());
  embedding.y.resize(states.size());
  for (size_t i = 0; i < states.size(); ++i) {
    embedding.x[i] = projected(i, 1);
    embedding.y[i] = projected(i, 0);
  }
  const double total = solver.eigenvalues().sum();
  embedding.explained = total > 0.0 ? solver.eigenvalues().tail<2>().sum() / total : 0.0;
  return embedding;
}

std::string SkillColor(int evaluation, int skill, int num_skills) {
  const int hue = kRunHues[evaluation % 6];
  const double lightness = 25.0 + 50.0 * skill / std::max(1, num_skills - 1);
  return "hsl(" + std::to_string(hue) + ",75%," + std::to_string(static_cast<int>(lightness)) + "%)";
}

SvgPlot CoverageFigure(const Evaluation& e, const std::string& title) {
  static const char* const kDimColors[kCoverageDims] = {"#d62728", "#ff7f0e", "#bcbd22", "#2ca02c",
                                                         "#17becf", "#1f77b4", "#9467bd"};
  const int skills = static_cast<int>(e.trajectories.size());
  SvgPlot plot(900, 420, {-0.6, skills - 0.4}, {-1.1, 1.1});
  plot.Title(title);
  plot.Labels("skill (dashed: did not survive 500 steps)", "normalised value");
  for (int d = 0; d < kCoverageDims; ++d) plot.Legend(kCoverageRanges[d].name, kDimColors[d]);
  for (const SkillTrajectory& s : e.trajectories) {
    if (s.points.empty()) continue;
    for (int d = 0; d < kCoverageDims; ++d) {
      double lo = INFINITY, hi = -INFINITY, sum = 0.0;
      for (const TrajectoryPoint& p : s.points) {
        const double v = std::clamp(NormalizedCoverageState(p)[d], -1.0, 1.0);
        lo = std::min(lo, v);
        hi = std::max(hi, v);
        sum += v;
      }
      const double x = s.skill + (d - (kCoverageDims - 1) / 2.0) * 0.11;
      plot.Line({x, x}, {lo, hi}, kDimColors[d], "", 4.0, !Counted(s));
      plot.Dot(x, sum / s.points.size(), 2.5, "black");
    }
  }
  return plot;
}

SvgPlot PsdFigure(const PsdBands& b, const std::string& title, double y_lo, double y_hi) {
  const double f_max = b.frequency.empty() ? 25.0 : b.frequency.back();
  SvgPlot plot(900, 420, {0.0, f_max}, {y_lo, y_hi});
  plot.Title(title);
  plot.Labels("frequency (Hz)", "PSD (dB re 1 (rad/s)^2/Hz)");
  std::vector<double> xs = b.frequency, ys = b.p95;
  xs.insert(xs.end(), b.frequency.rbegin(), b.frequency.rend());
  ys.insert(ys.end(), b.p5.rbegin(), b.p5.rend());
  plot.Polygon(xs, ys, "#cccccc");
  plot.Legend("5th-95th percentile", "#cccccc");
  plot.Line(b.frequency, b.q1, "#1f77b4", "lower quartile", 1.5, true);
  plot.Line(b.frequency, b.q3, "#2ca02c", "upper quartile", 1.5, true);
  plot.Line(b.frequency, b.median, "#d62728", "median");
  plot.Line({10.0, 10.0}, {y_lo, y_hi}, "#555555", "10 Hz cutoff", 1.0, true);
  return plot;
}

SvgPlot EmbeddingFigure(const Embedding& m, const std::vector<std::string>& labels, int num_skills) {
  SvgPlot plot(700, 600, SvgPlot::Covering(m.x), SvgPlot::Covering(m.y));
  char title[96];
  std::snprintf(title, sizeof title, "States projected on 2 principal components (%.0f %% of the variance)",
                100.0 * m.explained);
  plot.Title(title);
  plot.Labels("component 1", "component 2");
  for (size_t e = 0; e < labels.size(); ++e) {
    plot.Legend(labels[e], SkillColor(static_cast<int>(e), num_skills / 2, num_skills));
  }
  for (size_t i = 0; i < m.x.size(); ++i) plot.Dot(m.x[i], m.y[i], 1.6, SkillColor(m.evaluation[i], m.skill[i], num_skills));
  return plot;
}

SvgPlot MeanVelocityFigure(const std::vector<const Evaluation*>& evaluations, const std::vector<std::string>& labels,
                           int axis) {
  const bool yaw = axis == 2;
  std::vector<double> xs{-0.5, 0.5}, ys{yaw ? -0.7 : -0.5, yaw ? 0.7 : 0.5};
  for (const Evaluation* e : evaluations) {
    for (const SkillSummary& s : e->skills) {
      if (!Survives(s.survival_steps)) continue;
      xs.push_back(s.mean_linear_velocity[0]);
      ys.push_back(yaw ? s.mean_angular_velocity[2] : s.mean_linear_velocity[1]);
    }
  }
  SvgPlot plot(560, 480, SvgPlot::Covering(xs), SvgPlot::Covering(ys));
  plot.Title(yaw ? "Mean forward velocity and yaw rate per skill" : "Mean forward and lateral velocity per skill");
  plot.Labels("v_x (m/s)", yaw ? "w_z (rad/s)" : "v_y (m/s)");
  const SvgPlot::Range x = SvgPlot::Covering(xs), y = SvgPlot::Covering(ys);
  const double threshold = yaw ? 0.5 : 0.3;
  for (double v : {-0.3, 0.3}) plot.Line({v, v}, {y.lo, y.hi}, "#999999", "", 1.0, true);
  for (double v : {-threshold, threshold}) plot.Line({x.lo, x.hi}, {v, v}, "#999999", "", 1.0, true);
  for (size_t e = 0; e < evaluations.size(); ++e) {
    plot.Legend(labels[e], kRunColors[e % 6]);
    for (const SkillSummary& s : evaluations[e]->skills) {
      if (!Survives(s.survival_steps)) continue;
      plot.Dot(s.mean_linear_velocity[0], yaw ? s.mean_angular_velocity[2] : s.mean_linear_velocity[1], 5.0,
               kRunColors[e % 6]);
    }
  }
  return plot;
}

}  // namespace flsd
