// Fig. 5's spectrum bands and Fig. 6's embedding on trajectories with known answers.

#include "report/skill_figures.h"

#include <gtest/gtest.h>

#include <cmath>

namespace flsd {
namespace {

constexpr double kRate = 50.0;

// A skill whose joint `joint` velocity is amplitude * sin(2 pi f t), everything else still.
SkillTrajectory Sinusoid(int skill, int steps, int joint, double amplitude, double hz) {
  SkillTrajectory s;
  s.skill = skill;
  for (int t = 0; t < steps; ++t) {
    TrajectoryPoint p{};
    p.base_height = 0.3;
    p.joint_velocity[joint] = amplitude * std::sin(2.0 * M_PI * hz * t / kRate);
    s.points.push_back(p);
  }
  return s;
}

TEST(Percentile, InterpolatesBetweenOrderStatistics) {
  EXPECT_DOUBLE_EQ(Percentile({5, 1, 4, 2, 3}, 0.5), 3.0);
  EXPECT_DOUBLE_EQ(Percentile({5, 1, 4, 2, 3}, 0.25), 2.0);
  EXPECT_DOUBLE_EQ(Percentile({5, 1, 4, 2, 3}, 0.05), 1.2);
  EXPECT_DOUBLE_EQ(Percentile({5, 1, 4, 2, 3}, 1.0), 5.0);
  EXPECT_TRUE(std::isnan(Percentile({}, 0.5)));
}

TEST(JointVelocityPsdBands, SinusoidsOfKnownAmplitudePeakAtTheirFrequencyInDecibels) {
  // Amplitudes 1..4 at 5 Hz, 600 steps each: six 100-sample segments per skill. A sinusoid of
  // amplitude A whole in a segment of n samples has the one-sided density A^2 n / (2 rate) at its
  // bin: A^2 here, so 0, 6.02, 9.54 and 12.04 dB.
  std::vector<SkillTrajectory> skills;
  for (int k = 0; k < 4; ++k) skills.push_back(Sinusoid(k, 600, 2, k + 1.0, 5.0));
  skills.push_back(Sinusoid(4, 400, 2, 10.0, 5.0));  // did not survive 500 steps: not counted
  const PsdBands b = JointVelocityPsdBands(skills, 2, kRate, 100);
  EXPECT_EQ(b.segments, 24);
  ASSERT_EQ(b.frequency.size(), 51u);
  EXPECT_DOUBLE_EQ(b.frequency[10], 5.0);
  EXPECT_DOUBLE_EQ(b.frequency.back(), 25.0);
  EXPECT_NEAR(b.p5[10], 0.0, 1e-9);
  // The median of 24 samples, six of each: halfway between the 2nd and 3rd amplitudes' levels.
  EXPECT_NEAR(b.median[10], 0.5 * (10 * std::log10(4.0) + 10 * std::log10(9.0)), 1e-9);
  EXPECT_NEAR(b.p95[10], 10 * std::log10(16.0), 1e-9);
  EXPECT_LE(b.q1[10], b.median[10]);
  EXPECT_GE(b.q3[10], b.median[10]);
  // Away from 5 Hz the segments hold no power: the -100 dB floor.
  EXPECT_NEAR(b.p95[20], -100.0, 1e-9);
  // Another joint is still throughout.
  EXPECT_NEAR(JointVelocityPsdBands(skills, 5, kRate, 100).p95[10], -100.0, 1e-9);
}

TEST(JointVelocityPsdBands, NoSurvivingSkillGivesNoBands) {
  const PsdBands b = JointVelocityPsdBands({Sinusoid(0, 300, 2, 1.0, 5.0)}, 2, kRate, 100);
  EXPECT_EQ(b.segments, 0);
  EXPECT_TRUE(b.frequency.empty());
}

// Evaluations whose states vary in `varying` independent features (uncorrelated over whole
// periods), all the others constant.
Evaluation Varying(int varying) {
  Evaluation e;
  SkillTrajectory s;
  for (int t = 0; t < 1000; ++t) {
    TrajectoryPoint p{};
    const double phase = 2.0 * M_PI * t / 100.0;
    p.base_height = 0.3;
    p.linear_velocity[0] = std::sin(phase);
    if (varying > 1) p.angular_velocity[2] = 3.0 * std::cos(phase);      // another scale: standardised away
    if (varying > 2) p.joint_position[4] = 0.2 * std::sin(2.0 * phase);
    s.points.push_back(p);
  }
  e.trajectories.push_back(s);
  return e;
}

TEST(PrincipalComponentEmbedding, TwoComponentsHoldTheVarianceOfTwoOrThreeEqualFeatures) {
  const Evaluation two = Varying(2), three = Varying(3);
  const Embedding a = PrincipalComponentEmbedding({&two}, 1);
  EXPECT_EQ(a.x.size(), 1000u);
  EXPECT_NEAR(a.explained, 1.0, 1e-9);
  // Two standardised uncorrelated features: the points lie on a circle of radius sqrt(2).
  for (size_t i = 0; i < a.x.size(); i += 97) EXPECT_NEAR(std::hypot(a.x[i], a.y[i]), std::sqrt(2.0), 1e-2) << i;
  const Embedding b = PrincipalComponentEmbedding({&three, &two}, 10);
  EXPECT_EQ(b.x.size(), 200u);
  EXPECT_EQ(b.evaluation.front(), 0);
  EXPECT_EQ(b.evaluation.back(), 1);
  EXPECT_GT(b.explained, 0.66);
  EXPECT_LT(b.explained, 1.0 - 1e-3);
}

TEST(SkillFigures, ChartsRenderEveryMark) {
  Evaluation e = Varying(3);
  e.trajectories.push_back(Sinusoid(1, 300, 2, 1.0, 5.0));
  ComputeMetrics(e, kRate);
  const std::string coverage = CoverageFigure(e, "coverage").Render();
  // One bar per dimension per skill, the short skill's dashed.
  size_t dashed = 0;
  for (size_t at = coverage.find("stroke-dasharray"); at != std::string::npos; at = coverage.find("stroke-dasharray", at + 1)) {
    ++dashed;
  }
  EXPECT_EQ(dashed, static_cast<size_t>(kCoverageDims));
  EXPECT_NE(coverage.find("lin_vel_x"), std::string::npos);
  const std::string velocity = MeanVelocityFigure({&e}, {"run"}, 2).Render();
  EXPECT_NE(velocity.find("w_z (rad/s)"), std::string::npos);
}

}  // namespace
}  // namespace flsd
