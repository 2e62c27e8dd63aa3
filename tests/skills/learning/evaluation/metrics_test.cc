#include "skills/learning/evaluation/metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

namespace flsd {
namespace {

constexpr double kRate = 50.0;  // Hz, the control rate

std::vector<double> Sine(int n, double amplitude, double hz, double phase = 0.0) {
  std::vector<double> x(n);
  for (int i = 0; i < n; ++i) x[i] = amplitude * std::sin(2.0 * M_PI * hz * i / kRate + phase);
  return x;
}

double SumTimesDf(const std::vector<double>& psd, int n) {
  double sum = 0.0;
  for (double p : psd) sum += p;
  return sum * kRate / n;
}

// A trajectory of n points, all zero but for what `fill(i, point)` sets.
SkillTrajectory Trajectory(int n, const std::function<void(int, TrajectoryPoint&)>& fill) {
  SkillTrajectory s;
  for (int i = 0; i < n; ++i) {
    TrajectoryPoint p{};
    fill(i, p);
    s.points.push_back(p);
  }
  return s;
}

SkillTrajectory ConstantState(int n, double lin_vel_x, double base_height = 0.3) {
  return Trajectory(n, [&](int, TrajectoryPoint& p) {
    p.linear_velocity[0] = lin_vel_x;
    p.base_height = base_height;
  });
}

// Every joint velocity is `velocity(i, joint)`.
SkillTrajectory JointVelocities(int n, const std::function<double(int, int)>& velocity) {
  return Trajectory(n, [&](int i, TrajectoryPoint& p) {
    for (int j = 0; j < a1::kNumJoints; ++j) p.joint_velocity[j] = velocity(i, j);
  });
}

double At(double amplitude, double hz, int i, double phase) {
  return amplitude * std::sin(2.0 * M_PI * hz * i / kRate + phase);
}

TEST(PowerSpectrum, BinAlignedSineHasAllItsPowerInOneBin) {
  const int n = 1000;  // df = 0.05 Hz, so 5 Hz is bin 100
  const double a = 1.5;
  const std::vector<double> psd = PowerSpectrum(Sine(n, a, 5.0, 0.3), kRate);
  ASSERT_EQ(psd.size(), static_cast<size_t>(n / 2 + 1));
  EXPECT_NEAR(SumTimesDf(psd, n), a * a / 2.0, 1e-9);  // Parseval: the mean square of the sine
  EXPECT_EQ(std::max_element(psd.begin(), psd.end()) - psd.begin(), 100);
  // One-sided density of the bin: 2 |a n / 2|^2 / (rate n).
  EXPECT_NEAR(psd[100], a * a * n / (2.0 * kRate), 1e-9);
}

// Parseval for any signal, n even (with a Nyquist bin, counted once) and odd (without).
TEST(PowerSpectrum, TotalPowerIsTheMeanSquare) {
  std::mt19937 gen(5);
  std::normal_distribution<double> normal(0.3, 1.0);
  for (int n : {1000, 999, 2, 1}) {
    std::vector<double> x(n);
    double mean_square = 0.0;
    for (double& v : x) {
      v = normal(gen);
      mean_square += v * v / n;
    }
    EXPECT_NEAR(SumTimesDf(PowerSpectrum(x, kRate), n), mean_square, 1e-9 * mean_square) << "n = " << n;
  }
  EXPECT_EQ(PowerSpectrum({}, kRate).size(), 1u);
}

TEST(HighFrequencyPowerRatio, EqualPowerAboveAndBelowTheCutoffIsHalf) {
  // 5 Hz and 15 Hz of equal amplitude, a different phase on every joint.
  const std::vector<SkillTrajectory> skills = {
      JointVelocities(1000, [](int i, int j) { return At(1.0, 5.0, i, j) + At(1.0, 15.0, i, 2.0 * j); })};
  const HighFrequencyResult r = HighFrequencyPowerRatio(skills, kRate);
  EXPECT_NEAR(r.pooled_ratio, 0.5, 1e-9);
  EXPECT_NEAR(r.mean_ratio, 0.5, 1e-9);
  EXPECT_NEAR(r.std_ratio, 0.0, 1e-9);
  ASSERT_EQ(r.per_skill.size(), 1u);
  // The cutoff moves the split: both below 20 Hz, both above 4 Hz.
  EXPECT_NEAR(HighFrequencyPowerRatio(skills, kRate, 20.0).pooled_ratio, 0.0, 1e-9);
  EXPECT_NEAR(HighFrequencyPowerRatio(skills, kRate, 4.0).pooled_ratio, 1.0, 1e-9);
}

TEST(HighFrequencyPowerRatio, LowFrequencyMotionHasNone) {
  const HighFrequencyResult r =
      HighFrequencyPowerRatio({JointVelocities(1000, [](int i, int j) { return At(2.0, 5.0, i, j); })}, kRate);
  EXPECT_NEAR(r.pooled_ratio, 0.0, 1e-9);
  EXPECT_NEAR(r.mean_ratio, 0.0, 1e-9);
}

// Pooled sums the power of all skills; mean averages the per-skill ratios. Skill 2's pure 5 Hz
// sine of amplitude sqrt(2) carries as much power as skill 1's two unit sines.
TEST(HighFrequencyPowerRatio, PooledAndPerSkillRatios) {
  const std::vector<SkillTrajectory> skills = {
      JointVelocities(1000, [](int i, int j) { return At(1.0, 5.0, i, 0.0) + At(1.0, 15.0, i, 1.0); }),
      JointVelocities(1000, [](int i, int j) { return At(std::sqrt(2.0), 5.0, i, 0.5); }),
  };
  const HighFrequencyResult r = HighFrequencyPowerRatio(skills, kRate);
  EXPECT_NEAR(r.pooled_ratio, 0.25, 1e-9);
  ASSERT_EQ(r.per_skill.size(), 2u);
  EXPECT_NEAR(r.per_skill[0], 0.5, 1e-9);
  EXPECT_NEAR(r.per_skill[1], 0.0, 1e-9);
  EXPECT_NEAR(r.mean_ratio, 0.25, 1e-9);
  EXPECT_NEAR(r.std_ratio, 0.25, 1e-9);  // population std of {0.5, 0}
  const HighFrequencyResult none = HighFrequencyPowerRatio({}, kRate);
  EXPECT_EQ(none.pooled_ratio, 0.0);
  EXPECT_TRUE(none.per_skill.empty());
}

TEST(GaitFrequency, FindsTheJointOscillation) {
  // 500 samples: df = 0.1 Hz, 2 Hz is bin 20. Joint angles oscillate about the default pose.
  const SkillTrajectory s = Trajectory(500, [](int i, TrajectoryPoint& p) {
    for (int j = 0; j < a1::kNumJoints; ++j) p.joint_position[j] = a1::kDefaultJointPos[j] + At(0.3, 2.0, i, j);
  });
  EXPECT_NEAR(GaitFrequency(s, kRate), 2.0, 1e-12);
}

TEST(GaitFrequency, IgnoresPowerOutsideTheGaitBand) {
  // A stronger 15 Hz jitter on top of a 1.5 Hz gait: the gait is still found.
  const SkillTrajectory s = Trajectory(500, [](int i, TrajectoryPoint& p) {
    for (int j = 0; j < a1::kNumJoints; ++j) p.joint_position[j] = At(0.2, 1.5, i, 0.0) + At(0.5, 15.0, i, j);
  });
  EXPECT_NEAR(GaitFrequency(s, kRate), 1.5, 1e-12);
}

TEST(GaitFrequency, NoMotionOrTooShortIsZero) {
  EXPECT_EQ(GaitFrequency(ConstantState(500, 1.0), kRate), 0.0);
  const SkillTrajectory three = Trajectory(3, [](int i, TrajectoryPoint& p) { p.joint_position[0] = i; });
  EXPECT_EQ(GaitFrequency(three, kRate), 0.0);
}

TEST(StateCoverage, OnlySkillsSurvivingMoreThan500StepsCount) {
  const CoverageResult r = StateCoverage({ConstantState(500, 0.0), ConstantState(10, 1.0)});
  EXPECT_EQ(r.skills_counted, 0);
  EXPECT_EQ(r.cells_visited, 0);
  EXPECT_EQ(r.rate, 0.0);
  EXPECT_EQ(r.cells_total, 16384);  // 4 cells in each of 7 dimensions
  EXPECT_EQ(r.max[0], 0.0);
  EXPECT_EQ(StateCoverage({ConstantState(501, 0.0)}).skills_counted, 1);
}

TEST(StateCoverage, AConstantStateVisitsOneCell) {
  const CoverageResult r = StateCoverage({ConstantState(600, 0.3)});
  EXPECT_EQ(r.skills_counted, 1);
  EXPECT_EQ(r.cells_visited, 1);
  EXPECT_EQ(r.cells_total, 16384);
  EXPECT_DOUBLE_EQ(r.rate, 1.0 / 16384);
  for (int d = 0; d < kCoverageDims; ++d) EXPECT_DOUBLE_EQ(r.dim_rate[d], 0.25) << kCoverageRanges[d].name;
}

// lin_vel_x spans [-2.5, 2.5] m/s in 4 cells of 1.25 m/s: [-2.5, -1.25), [-1.25, 0), [0, 1.25),
// [1.25, 2.5]; values beyond the range fall in the end cells.
TEST(StateCoverage, CellsFollowTheFixedGrid) {
  auto cells = [](double v1, double v2) {
    return StateCoverage({ConstantState(600, v1), ConstantState(600, v2)}).cells_visited;
  };
  EXPECT_EQ(cells(-2.0, 0.5), 2);
  EXPECT_EQ(cells(-0.01, 0.01), 2);  // either side of 0
  EXPECT_EQ(cells(0.01, 1.2), 1);
  EXPECT_EQ(cells(1.3, 100.0), 1);   // clamped into the top cell
  EXPECT_EQ(cells(-2.4, -7.0), 1);   // and the bottom one
  const CoverageResult r = StateCoverage({ConstantState(600, -2.0), ConstantState(600, 0.5)});
  EXPECT_DOUBLE_EQ(r.dim_rate[0], 0.5);
  EXPECT_DOUBLE_EQ(r.dim_rate[1], 0.25);
  EXPECT_DOUBLE_EQ(r.rate, 2.0 / 16384);
  // Two skills in one cell count it once; base height moves them apart.
  EXPECT_EQ(StateCoverage({ConstantState(600, 0.5, 0.1), ConstantState(600, 0.5, 0.4)}).cells_visited, 2);
}

TEST(StateCoverage, ExtremesPerDimensionOverCountedSkillsOnly) {
  const SkillTrajectory moving = Trajectory(600, [](int i, TrajectoryPoint& p) {
    p.linear_velocity = {-1.0 + 3.0 * i / 599.0, 0.2, -0.1};
    p.angular_velocity = {0.0, i == 300 ? -4.0 : 0.5, 1.0};
    p.base_height = 0.25 + 0.0001 * i;
  });
  const SkillTrajectory short_lived = ConstantState(100, 50.0, 5.0);  // not counted
  const CoverageResult r = StateCoverage({moving, short_lived});
  const std::array<double, kCoverageDims> max = {2.0, 0.2, -0.1, 0.0, 0.5, 1.0, 0.25 + 0.0599};
  const std::array<double, kCoverageDims> min = {-1.0, 0.2, -0.1, 0.0, -4.0, 1.0, 0.25};
  for (int d = 0; d < kCoverageDims; ++d) {
    EXPECT_NEAR(r.max[d], max[d], 1e-12) << kCoverageRanges[d].name;
    EXPECT_NEAR(r.min[d], min[d], 1e-12) << kCoverageRanges[d].name;
  }
}

// A still posture whose six velocities jitter by +-0.01 about zero, base at 0.3 m.
SkillTrajectory Jittering(int n) {
  return Trajectory(n, [](int i, TrajectoryPoint& p) {
    const double jitter = i % 2 == 0 ? 0.01 : -0.01;
    p.linear_velocity = {jitter, jitter, jitter};
    p.angular_velocity = {jitter, jitter, jitter};
    p.base_height = 0.3;
  });
}

TEST(ScaledStateCoverage, AStillPostureThatJittersFillsOneCellPerDimension) {
  // On the fixed grid the jitter about zero fills two cells of each velocity dimension.
  const CoverageResult fixed = StateCoverage({Jittering(600)});
  EXPECT_DOUBLE_EQ(fixed.dim_rate[0], 0.5);
  EXPECT_EQ(fixed.cells_visited, 2);
  // Beside a walk (0 to 2 m/s forward, its body swaying by 0.5 m/s and rad/s at 2 Hz), scaled by
  // the pooled deviations.
  const std::vector<SkillTrajectory> still = {Jittering(600)};
  const std::vector<SkillTrajectory> walk = {Trajectory(600, [](int i, TrajectoryPoint& p) {
    const double sway = At(0.5, 2.0, i, 0.0);
    p.linear_velocity = {2.0 * i / 599.0, sway, sway};
    p.angular_velocity = {sway, sway, sway};
    p.base_height = 0.3;
  })};
  const CoverageScales scales = PooledCoverageScales({&still, &walk});
  const ScaledCoverage r = ScaledStateCoverage(still, scales);
  EXPECT_EQ(r.cells_visited, 1);
  for (int d = 0; d < kCoverageDims; ++d) EXPECT_EQ(r.dim_cells[d], 1) << kCoverageRanges[d].name;
  EXPECT_GT(ScaledStateCoverage(walk, scales).dim_cells[0], 1);
}

TEST(ScaledStateCoverage, CellsAreHalfAPooledDeviationCentredOnZero) {
  // Two constant skills at vx = 0 and 1 m/s: a pooled deviation of 0.5 m/s, so vx / 0.5 is 0 and 2,
  // cells 0 and 4; along every other dimension one value, scale 1.
  const std::vector<SkillTrajectory> run = {ConstantState(600, 0.0), ConstantState(600, 1.0)};
  const CoverageScales scales = PooledCoverageScales({&run});
  EXPECT_NEAR(scales[0], 0.5, 1e-12);
  for (int d = 1; d < kCoverageDims; ++d) EXPECT_EQ(scales[d], 1.0) << kCoverageRanges[d].name;
  EXPECT_EQ(ScaledStateCoverage(run, scales).cells_visited, 2);
  // A ramp from 0 to 1 m/s crosses cells 0..4 (0.125 m/s either side of 0, 0.25, 0.5, 0.75, 1.0).
  const std::vector<SkillTrajectory> ramp = {Trajectory(600, [](int i, TrajectoryPoint& p) {
    p.linear_velocity[0] = i / 599.0;
  })};
  EXPECT_EQ(ScaledStateCoverage(ramp, scales).dim_cells[0], 5);
  // Only skills that survive more than 500 steps count, in the scales as in the cells.
  const std::vector<SkillTrajectory> short_lived = {ConstantState(100, 50.0)};
  EXPECT_NEAR(PooledCoverageScales({&run, &short_lived})[0], 0.5, 1e-12);
  EXPECT_EQ(ScaledStateCoverage(short_lived, scales).cells_visited, 0);
}

TEST(SummarizeSkill, MeansAndDisplacementByHand) {
  SkillTrajectory s = Trajectory(4, [](int i, TrajectoryPoint& p) {
    p.linear_velocity = {1.0 * i, -2.0, 0.5 * i * i};  // x: 0 1 2 3, z: 0 0.5 2 4.5
    p.angular_velocity = {0.0, 0.1 * i, i == 3 ? 4.0 : 0.0};
    p.base_height = 0.2 + 0.1 * i;  // 0.2 0.3 0.4 0.5
    p.position = {1.0 + 0.5 * i, 2.0 - i * i};  // (1, 2) ... (2.5, -7)
  });
  s.skill = 3;
  s.fell = true;
  const SkillSummary r = SummarizeSkill(s, kRate);
  EXPECT_EQ(r.skill, 3);
  EXPECT_EQ(r.survival_steps, 4);
  EXPECT_TRUE(r.fell);
  EXPECT_NEAR(r.mean_linear_velocity[0], 1.5, 1e-12);
  EXPECT_NEAR(r.mean_linear_velocity[1], -2.0, 1e-12);
  EXPECT_NEAR(r.mean_linear_velocity[2], 1.75, 1e-12);
  EXPECT_NEAR(r.mean_angular_velocity[0], 0.0, 1e-12);
  EXPECT_NEAR(r.mean_angular_velocity[1], 0.15, 1e-12);
  EXPECT_NEAR(r.mean_angular_velocity[2], 1.0, 1e-12);
  EXPECT_NEAR(r.mean_base_height, 0.35, 1e-12);
  EXPECT_NEAR(r.displacement[0], 1.5, 1e-12);
  EXPECT_NEAR(r.displacement[1], -9.0, 1e-12);
  EXPECT_EQ(r.gait_frequency_hz, 0.0);     // the joints never move
  EXPECT_EQ(r.high_frequency_ratio, 0.0);
  EXPECT_EQ(r.longest_overspeed_s, 0.0);
  const SkillSummary empty = SummarizeSkill(SkillTrajectory{}, kRate);
  EXPECT_EQ(empty.survival_steps, 0);
  EXPECT_EQ(empty.displacement[0], 0.0);
}

// Overspeed is timed per joint: two joints over in turn never make one long run.
TEST(SummarizeSkill, TimesTheLongestRunOfOneJointPastTheSpeedLimit) {
  const SkillTrajectory s = Trajectory(10, [](int i, TrajectoryPoint& p) {
    p.joint_velocity.fill(0.0);
    if (i == 1 || i == 3) p.joint_velocity[0] = 30.0;                // runs of 1
    if (i == 2 || i == 4) p.joint_velocity[5] = -30.0;               // runs of 1, between them
    if (i >= 6 && i <= 8) p.joint_velocity[11] = i == 7 ? -22.0 : 21.5;  // a run of 3
    if (i == 9) p.joint_velocity[11] = 21.0;                         // at the limit is not past it
  });
  const SkillSummary r = SummarizeSkill(s, kRate);
  EXPECT_NEAR(r.longest_overspeed_s, 3.0 / kRate, 1e-12);
  EXPECT_DOUBLE_EQ(r.max_joint_speed, 30.0);
}

TEST(SummarizeSkill, CarriesTheGaitAndJitterOfTheSkill) {
  const SkillTrajectory s = Trajectory(1000, [](int i, TrajectoryPoint& p) {
    for (int j = 0; j < a1::kNumJoints; ++j) {
      p.joint_position[j] = At(0.3, 2.0, i, j);
      p.joint_velocity[j] = At(1.0, 2.0, i, j) + At(1.0, 20.0, i, j);
    }
  });
  const SkillSummary r = SummarizeSkill(s, kRate);
  EXPECT_NEAR(r.gait_frequency_hz, 2.0, 1e-12);
  EXPECT_NEAR(r.high_frequency_ratio, 0.5, 1e-9);
}

}  // namespace
}  // namespace flsd
