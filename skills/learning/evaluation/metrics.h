#pragma once
// The paper's skill metrics (Sec. IV-B), computed from recorded trajectories. Plain C++: no torch.
//
// State coverage. The paper normalises "each dimension" of (lin. vel. xyz, ang. vel. xyz, base
// height) and counts the visited cells of a grid of step 0.5, without saying how it normalises or
// what it divides by. Here each dimension is mapped to [-1, 1] by a fixed reference range that
// encloses the extremes of the paper's Table I (kCoverageRanges), so every run is measured on the
// same grid: 4 cells per dimension, 4^7 = 16384 cells in all; the coverage rate is the fraction of
// them that the trajectories of the skills surviving more than 500 steps visit.
//
// The paper's "normalised in each dimension" read a second way (ScaledStateCoverage): each dimension
// divided by its standard deviation over the states of all the runs compared, cells of 0.5 of it
// centred on zero. A still robot whose velocities jitter by less than a quarter of a deviation then
// fills one cell per dimension, where on the fixed grid a jitter about zero fills two.
//
// High-frequency power ratio (Table II): the one-sided power spectrum of each joint velocity
// trajectory by DFT; the ratio is the power above 10 Hz over the total power (DC included),
// summed over the joints and skills pooled, and also averaged per skill.

#include <array>
#include <string>
#include <vector>

#include "robot/a1.h"
#include "skills/runtime/library_format.h"
#include "skills/runtime/skill_library.h"
#include "skills/learning/tasks/velocity_tracking.h"

namespace flsd {

// One control step of a skill's evaluation rollout, in physical units.
struct TrajectoryPoint {
  std::array<double, 3> linear_velocity;   // body frame, m/s
  std::array<double, 3> angular_velocity;  // body frame, rad/s
  double base_height;                      // m
  std::array<double, 2> position;          // world x, y, m
  a1::JointArray<double> joint_position;   // rad
  a1::JointArray<double> joint_velocity;   // rad/s
  double stance_foot_speed = 0.0;          // m/s, mean over the feet in contact (sim only)
};

struct SkillTrajectory {
  int skill = 0;
  bool fell = false;  // ended by a failure rather than by running its full length
  std::vector<TrajectoryPoint> points;
};

inline constexpr int kCoverageDims = 7;
struct CoverageRange {
  const char* name;
  double lo, hi;
};
inline constexpr std::array<CoverageRange, kCoverageDims> kCoverageRanges = {{
    {"lin_vel_x", -2.5, 2.5},
    {"lin_vel_y", -2.0, 2.0},
    {"lin_vel_z", -3.0, 3.0},
    {"ang_vel_x", -25.0, 25.0},
    {"ang_vel_y", -10.0, 10.0},
    {"ang_vel_z", -10.0, 10.0},
    {"base_height", 0.0, 0.5},
}};
inline constexpr double kCoverageCell = 0.5;        // grid step in normalised units

struct CoverageResult {
  int skills_counted = 0;       // skills that survive (Survives)
  long cells_visited = 0;
  long cells_total = 0;
  double rate = 0.0;            // cells_visited / cells_total
  std::array<double, kCoverageDims> max{}, min{};  // Table I, over the counted skills
  std::array<double, kCoverageDims> dim_rate{};    // 1-D coverage of each dimension alone
};
CoverageResult StateCoverage(const std::vector<SkillTrajectory>& skills);

// Per dimension, the standard deviation of the coverage states of the surviving skills of every
// run given, pooled (1 where a dimension does not vary, so that its one value is one cell).
using CoverageScales = std::array<double, kCoverageDims>;
CoverageScales PooledCoverageScales(const std::vector<const std::vector<SkillTrajectory>*>& runs);
struct ScaledCoverage {
  long cells_visited = 0;                          // of the 7-D grid
  std::array<long, kCoverageDims> dim_cells{};     // Fig. 4: cells along each dimension alone
};
// The surviving skills' states divided by `scales`, counted on cells of kCoverageCell centred on zero.
ScaledCoverage ScaledStateCoverage(const std::vector<SkillTrajectory>& skills, const CoverageScales& scales);
// A point's coverage dimensions mapped by kCoverageRanges to [-1, 1] (not clamped).
std::array<double, kCoverageDims> NormalizedCoverageState(const TrajectoryPoint& p);

// One-sided power spectral density of x sampled at rate_hz (periodogram, (rad/s)^2/Hz):
// element j is the density at j * rate_hz / n, j = 0..n/2.
std::vector<double> PowerSpectrum(const std::vector<double>& x, double rate_hz);

struct HighFrequencyResult {
  double pooled_ratio = 0.0;     // sum of power above cutoff / sum of power, joints and skills pooled
  double mean_ratio = 0.0;       // per-skill ratio, averaged over skills
  double std_ratio = 0.0;
  std::vector<double> per_skill;  // in input order
};
HighFrequencyResult HighFrequencyPowerRatio(const std::vector<SkillTrajectory>& skills, double rate_hz,
                                            double cutoff_hz = 10.0);

// The dominant frequency (Hz) of the joint angles in [0.5, 10] Hz (the spectral peak of the sum
// of the mean-removed joint angles' spectra); 0 for a trajectory too short or without motion.
double GaitFrequency(const SkillTrajectory& skill, double rate_hz);

struct SkillSummary {
  int skill = 0;
  int survival_steps = 0;
  bool fell = false;
  std::array<double, 3> mean_linear_velocity{};   // body frame, m/s
  std::array<double, 3> mean_angular_velocity{};  // body frame, rad/s
  double mean_base_height = 0.0;
  double gait_frequency_hz = 0.0;
  double high_frequency_ratio = 0.0;
  double mean_stance_foot_speed = 0.0;  // m/s: how much the feet slide while they bear weight
  double max_joint_speed = 0.0;         // rad/s, over all joints
  // s, the longest one joint stays past a1::kJointVelocityLimit without a break: beyond
  // a1::kJointOverspeedTolerance, skilld's supervisor stops the skill.
  double longest_overspeed_s = 0.0;
  std::array<double, 2> displacement{};  // world x, y, m
  // legged_gym's velocity-task reward per second (scaled terms, unclipped total) when the skill is
  // commanded its own mean velocity: the most a skill selector could earn from it (flsd eval).
  VelocityRewardTerms task_reward_per_s{};
};
SkillSummary SummarizeSkill(const SkillTrajectory& skill, double rate_hz);
// What a library records of a skill from its evaluation and (optionally) its randomised one: the
// measured fields of its descriptor (the id as its index, one policy).
SkillDescriptor DescribeSkill(const SkillSummary& nominal, const SkillSummary* randomized = nullptr);

// One rollout of every skill and the paper's metrics over it (flsd eval, flsd report).
struct Evaluation {
  std::string method;
  int steps = 0;
  bool randomized = false;
  int starts = 1;  // per skill: survival and falls the worst of them, slip their mean (EvaluateOverStarts)
  std::vector<SkillTrajectory> trajectories;  // one per skill, up to its first termination
  std::vector<SkillSummary> skills;
  std::vector<int> mirror_skill;  // per skill, the skill trained as its mirror image (itself if none)
  int survivors = 0;  // skills that survive (Survives: kSurvivalSteps)
  CoverageResult coverage;
  HighFrequencyResult high_frequency;
};
// Fills skills, survivors, coverage and high_frequency from the trajectories.
void ComputeMetrics(Evaluation& evaluation, double rate_hz);

}  // namespace flsd
