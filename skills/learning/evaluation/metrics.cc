#include "skills/learning/evaluation/metrics.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <set>
#include <unordered_set>

#include "robot/joint_limit_timer.h"

namespace flsd {
namespace {

std::array<double, kCoverageDims> CoverageState(const TrajectoryPoint& p) {
  return {p.linear_velocity[0], p.linear_velocity[1], p.linear_velocity[2], p.angular_velocity[0],
          p.angular_velocity[1], p.angular_velocity[2], p.base_height};
}

constexpr int CellsPerDim() { return static_cast<int>(2.0 / kCoverageCell); }

// Cell index of a normalised value: [-1, 1] in steps of kCoverageCell, clamped at the ends.
int CellOf(double normalised) {
  const int cell = static_cast<int>(std::floor((normalised + 1.0) / kCoverageCell));
  return std::clamp(cell, 0, CellsPerDim() - 1);
}

int SurvivalSteps(const SkillTrajectory& s) { return static_cast<int>(s.points.size()); }

// sum over bins above `cutoff` and over all bins, of x's one-sided spectrum.
std::pair<double, double> BandPower(const std::vector<double>& x, double rate_hz, double cutoff_hz) {
  const std::vector<double> psd = PowerSpectrum(x, rate_hz);
  const double df = rate_hz / static_cast<double>(x.size());
  double high = 0.0, total = 0.0;
  for (size_t j = 0; j < psd.size(); ++j) {
    total += psd[j] * df;
    if (j * df > cutoff_hz) high += psd[j] * df;
  }
  return {high, total};
}

std::vector<double> JointSeries(const SkillTrajectory& s, int joint, bool velocity) {
  std::vector<double> x;
  x.reserve(s.points.size());
  for (const TrajectoryPoint& p : s.points) x.push_back(velocity ? p.joint_velocity[joint] : p.joint_position[joint]);
  return x;
}

}  // namespace

std::array<double, kCoverageDims> NormalizedCoverageState(const TrajectoryPoint& p) {
  std::array<double, kCoverageDims> x = CoverageState(p);
  for (int d = 0; d < kCoverageDims; ++d) {
    const CoverageRange& r = kCoverageRanges[d];
    x[d] = 2.0 * (x[d] - r.lo) / (r.hi - r.lo) - 1.0;
  }
  return x;
}

CoverageResult StateCoverage(const std::vector<SkillTrajectory>& skills) {
  CoverageResult r;
  r.max.fill(-INFINITY);
  r.min.fill(INFINITY);
  std::unordered_set<long> cells;
  std::array<std::unordered_set<int>, kCoverageDims> dim_cells;
  for (const SkillTrajectory& s : skills) {
    if (!Survives(SurvivalSteps(s))) continue;
    ++r.skills_counted;
    for (const TrajectoryPoint& p : s.points) {
      const std::array<double, kCoverageDims> x = CoverageState(p);
      const std::array<double, kCoverageDims> normalised = NormalizedCoverageState(p);
      long key = 0;
      for (int d = 0; d < kCoverageDims; ++d) {
        r.max[d] = std::max(r.max[d], x[d]);
        r.min[d] = std::min(r.min[d], x[d]);
        const int cell = CellOf(normalised[d]);
        dim_cells[d].insert(cell);
        key = key * CellsPerDim() + cell;
      }
      cells.insert(key);
    }
  }
  if (r.skills_counted == 0) {
    r.max.fill(0.0);
    r.min.fill(0.0);
  }
  r.cells_total = static_cast<long>(std::pow(CellsPerDim(), kCoverageDims));
  r.cells_visited = static_cast<long>(cells.size());
  r.rate = static_cast<double>(r.cells_visited) / static_cast<double>(r.cells_total);
  for (int d = 0; d < kCoverageDims; ++d) r.dim_rate[d] = double(dim_cells[d].size()) / CellsPerDim();
  return r;
}

CoverageScales PooledCoverageScales(const std::vector<const std::vector<SkillTrajectory>*>& runs) {
  // Two passes, so that a dimension that never varies has a deviation of exactly zero.
  auto over_states = [&](const std::function<void(const std::array<double, kCoverageDims>&)>& visit) {
    for (const std::vector<SkillTrajectory>* run : runs) {
      for (const SkillTrajectory& s : *run) {
        if (!Survives(SurvivalSteps(s))) continue;
        for (const TrajectoryPoint& p : s.points) visit(CoverageState(p));
      }
    }
  };
  std::array<double, kCoverageDims> mean{}, variance{};
  double count = 0.0;
  over_states([&](const std::array<double, kCoverageDims>& x) {
    for (int d = 0; d < kCoverageDims; ++d) mean[d] += x[d];
    count += 1.0;
  });
  for (double& m : mean) m = count > 0.0 ? m / count : 0.0;
  over_states([&](const std::array<double, kCoverageDims>& x) {
    for (int d = 0; d < kCoverageDims; ++d) variance[d] += (x[d] - mean[d]) * (x[d] - mean[d]) / count;
  });
  CoverageScales scales;
  for (int d = 0; d < kCoverageDims; ++d) scales[d] = variance[d] > 1e-18 ? std::sqrt(variance[d]) : 1.0;
  return scales;
}

ScaledCoverage ScaledStateCoverage(const std::vector<SkillTrajectory>& skills, const CoverageScales& scales) {
  std::set<std::array<long, kCoverageDims>> cells;
  std::array<std::set<long>, kCoverageDims> dim_cells;
  for (const SkillTrajectory& s : skills) {
    if (!Survives(SurvivalSteps(s))) continue;
    for (const TrajectoryPoint& p : s.points) {
      const std::array<double, kCoverageDims> x = CoverageState(p);
      std::array<long, kCoverageDims> cell;
      for (int d = 0; d < kCoverageDims; ++d) {
        cell[d] = std::lround(x[d] / scales[d] / kCoverageCell);  // cell 0 is [-0.25, 0.25) deviations
        dim_cells[d].insert(cell[d]);
      }
      cells.insert(cell);
    }
  }
  ScaledCoverage r;
  r.cells_visited = static_cast<long>(cells.size());
  for (int d = 0; d < kCoverageDims; ++d) r.dim_cells[d] = static_cast<long>(dim_cells[d].size());
  return r;
}

std::vector<double> PowerSpectrum(const std::vector<double>& x, double rate_hz) {
  const size_t n = x.size();
  std::vector<double> psd(n / 2 + 1, 0.0);
  if (n == 0) return psd;
  // A direct DFT over a table of the n roots of unity: trajectories are at most a few thousand
  // samples, evaluated offline.
  std::vector<std::complex<double>> roots(n);
  for (size_t k = 0; k < n; ++k) roots[k] = std::polar(1.0, -2.0 * M_PI * double(k) / double(n));
  for (size_t j = 0; j <= n / 2; ++j) {
    std::complex<double> sum = 0.0;
    for (size_t t = 0; t < n; ++t) sum += x[t] * roots[(j * t) % n];
    const bool two_sided_pair = j != 0 && !(n % 2 == 0 && j == n / 2);
    psd[j] = (two_sided_pair ? 2.0 : 1.0) * std::norm(sum) / (rate_hz * double(n));
  }
  return psd;
}

HighFrequencyResult HighFrequencyPowerRatio(const std::vector<SkillTrajectory>& skills, double rate_hz,
                                            double cutoff_hz) {
  HighFrequencyResult r;
  double pooled_high = 0.0, pooled_total = 0.0;
  for (const SkillTrajectory& s : skills) {
    double high = 0.0, total = 0.0;
    for (int j = 0; j < a1::kNumJoints; ++j) {
      const auto [h, t] = BandPower(JointSeries(s, j, /*velocity=*/true), rate_hz, cutoff_hz);
      high += h;
      total += t;
    }
    pooled_high += high;
    pooled_total += total;
    r.per_skill.push_back(total > 0.0 ? high / total : 0.0);
  }
  r.pooled_ratio = pooled_total > 0.0 ? pooled_high / pooled_total : 0.0;
  if (!r.per_skill.empty()) {
    double sum = 0.0, sq = 0.0;
    for (double v : r.per_skill) sum += v;
    r.mean_ratio = sum / r.per_skill.size();
    for (double v : r.per_skill) sq += (v - r.mean_ratio) * (v - r.mean_ratio);
    r.std_ratio = std::sqrt(sq / r.per_skill.size());
  }
  return r;
}

double GaitFrequency(const SkillTrajectory& s, double rate_hz) {
  const size_t n = s.points.size();
  if (n < 4) return 0.0;
  std::vector<double> summed(n / 2 + 1, 0.0);
  for (int j = 0; j < a1::kNumJoints; ++j) {
    std::vector<double> x = JointSeries(s, j, /*velocity=*/false);
    double mean = 0.0;
    for (double v : x) mean += v;
    mean /= double(n);
    for (double& v : x) v -= mean;
    const std::vector<double> psd = PowerSpectrum(x, rate_hz);
    for (size_t k = 0; k < psd.size(); ++k) summed[k] += psd[k];
  }
  const double df = rate_hz / double(n);
  double best = 0.0, best_power = 1e-12;
  for (size_t k = 1; k < summed.size(); ++k) {
    const double f = k * df;
    if (f < 0.5 || f > 10.0) continue;
    if (summed[k] > best_power) {
      best_power = summed[k];
      best = f;
    }
  }
  return best;
}

SkillDescriptor DescribeSkill(const SkillSummary& s, const SkillSummary* randomized) {
  SkillDescriptor d;
  d.id = d.mirror_skill = d.policy_skill = s.skill;
  d.mean_linear_velocity = Eigen::Vector3d(s.mean_linear_velocity.data());
  d.mean_angular_velocity = Eigen::Vector3d(s.mean_angular_velocity.data());
  d.mean_base_height = s.mean_base_height;
  d.mean_stance_foot_speed = s.mean_stance_foot_speed;
  d.gait_frequency_hz = s.gait_frequency_hz;
  d.survival_steps = s.survival_steps;
  d.fell = s.fell;
  if (randomized) {
    d.randomized_survival_steps = randomized->survival_steps;
    d.randomized_stance_foot_speed = randomized->mean_stance_foot_speed;
    d.randomized_fell = randomized->fell;
  }
  return d;
}

SkillSummary SummarizeSkill(const SkillTrajectory& s, double rate_hz) {
  SkillSummary r;
  r.skill = s.skill;
  r.survival_steps = SurvivalSteps(s);
  r.fell = s.fell;
  if (s.points.empty()) return r;
  JointLimitTimer overspeed;
  for (const TrajectoryPoint& p : s.points) {
    r.longest_overspeed_s = std::max(
        r.longest_overspeed_s, overspeed.Update(FasterThan(p.joint_velocity, a1::kJointVelocityLimit), 1.0 / rate_hz));
    for (int k = 0; k < 3; ++k) {
      r.mean_linear_velocity[k] += p.linear_velocity[k];
      r.mean_angular_velocity[k] += p.angular_velocity[k];
    }
    r.mean_base_height += p.base_height;
    r.mean_stance_foot_speed += p.stance_foot_speed;
    for (double qd : p.joint_velocity) r.max_joint_speed = std::max(r.max_joint_speed, std::abs(qd));
  }
  const double n = static_cast<double>(s.points.size());
  for (int k = 0; k < 3; ++k) {
    r.mean_linear_velocity[k] /= n;
    r.mean_angular_velocity[k] /= n;
  }
  r.mean_base_height /= n;
  r.mean_stance_foot_speed /= n;
  r.gait_frequency_hz = GaitFrequency(s, rate_hz);
  r.high_frequency_ratio = HighFrequencyPowerRatio({s}, rate_hz).pooled_ratio;
  r.displacement = {s.points.back().position[0] - s.points.front().position[0],
                    s.points.back().position[1] - s.points.front().position[1]};
  return r;
}

void ComputeMetrics(Evaluation& e, double rate_hz) {
  e.skills.clear();
  e.survivors = 0;
  for (const SkillTrajectory& s : e.trajectories) {
    e.skills.push_back(SummarizeSkill(s, rate_hz));
    e.survivors += Survives(static_cast<int>(s.points.size()));
  }
  e.coverage = StateCoverage(e.trajectories);
  e.high_frequency = HighFrequencyPowerRatio(e.trajectories, rate_hz);
}

}  // namespace flsd
