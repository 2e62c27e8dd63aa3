// The report's numbers (FLSD against DIAYN, directions, survival) and the files it writes.

#include "report/skill_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/common/test_support.h"

namespace flsd {
namespace {

constexpr double kRate = 50.0;

// A skill moving at (vx, vy, wz) for `steps` with joint 2 oscillating at `hz`.
SkillTrajectory Moving(int skill, int steps, double vx, double vy, double wz, double hz) {
  SkillTrajectory s;
  s.skill = skill;
  for (int t = 0; t < steps; ++t) {
    TrajectoryPoint p{};
    p.linear_velocity = {vx, vy, 0.0};
    p.angular_velocity = {0.0, 0.0, wz};
    p.base_height = 0.25 + 0.01 * skill;
    p.joint_velocity[2] = std::sin(2.0 * M_PI * hz * t / kRate);
    s.points.push_back(p);
  }
  s.fell = steps < 600;
  return s;
}

ReportRun Run(const std::string& label, const std::string& method, std::vector<SkillTrajectory> nominal,
              std::vector<SkillTrajectory> randomized) {
  ReportRun r;
  r.label = label;
  r.method = method;
  r.env_steps = 1000000;
  r.nominal.steps = 600;
  r.nominal.trajectories = std::move(nominal);
  r.randomized.trajectories = std::move(randomized);
  ComputeMetrics(r.nominal, kRate);
  ComputeMetrics(r.randomized, kRate);
  return r;
}

std::vector<ReportRun> TwoMethods() {
  // FLSD: forward, backward-turning, sideways and a skill that falls; smooth (2 Hz).
  // DIAYN: two still skills that jitter at 20 Hz, one of which falls with randomisation.
  return {Run("flsd_s1", "flsd",
              {Moving(0, 600, 0.5, 0.0, 0.0, 2), Moving(1, 600, -0.4, 0.0, -0.8, 2), Moving(2, 600, 0.0, 0.35, 0.0, 2),
               Moving(3, 100, 1.0, 0.0, 0.0, 2)},
              {Moving(0, 600, 0.5, 0.0, 0.0, 2), Moving(1, 600, -0.4, 0.0, -0.8, 2), Moving(2, 200, 0.0, 0.35, 0.0, 2),
               Moving(3, 100, 1.0, 0.0, 0.0, 2)}),
          Run("diayn_s1", "diayn", {Moving(0, 600, 0.0, 0.0, 0.0, 20), Moving(1, 600, 0.0, 0.0, 0.0, 20)},
              {Moving(0, 600, 0.0, 0.0, 0.0, 20), Moving(1, 50, 0.0, 0.0, 0.0, 20)})};
}

TEST(SkillReport, CountsDirectionsAndRobustSurvivorsOfSkillsThatSurvive) {
  const std::vector<ReportRun> runs = TwoMethods();
  const DirectionCounts n = CountDirections(runs[0].nominal);
  EXPECT_EQ(n.forward, 1);  // skill 3 is faster but fell
  EXPECT_EQ(n.backward, 1);
  EXPECT_EQ(n.sideways, 1);
  EXPECT_EQ(n.turning, 1);
  EXPECT_EQ(runs[0].nominal.survivors, 3);
  EXPECT_EQ(RobustSurvivors(runs[0]), 2);
  EXPECT_EQ(RobustSurvivors(runs[1]), 1);
}

TEST(SkillReport, ComparesFlsdWithDiaynAsRatiosOfTheMethodMeans) {
  const std::vector<ReportRun> runs = TwoMethods();
  const nlohmann::json json = ReportJson(runs);
  const double flsd_rate = runs[0].nominal.coverage.rate, diayn_rate = runs[1].nominal.coverage.rate;
  EXPECT_GT(flsd_rate, diayn_rate);
  EXPECT_DOUBLE_EQ(json["comparison"]["coverage_ratio"].get<double>(), flsd_rate / diayn_rate);
  const double high = runs[0].nominal.high_frequency.pooled_ratio / runs[1].nominal.high_frequency.pooled_ratio;
  EXPECT_DOUBLE_EQ(json["comparison"]["high_frequency_ratio"].get<double>(), high);
  EXPECT_DOUBLE_EQ(json["comparison"]["high_frequency_reduction"].get<double>(), 1.0 - high);
  // 2 Hz against 20 Hz: DIAYN's power is all above the 10 Hz cutoff, FLSD's none of it.
  EXPECT_NEAR(runs[1].nominal.high_frequency.pooled_ratio, 1.0, 1e-6);
  EXPECT_LT(runs[0].nominal.high_frequency.pooled_ratio, 1e-6);
  EXPECT_NEAR(json["comparison"]["paper"]["coverage_ratio"].get<double>(), 2.33, 0.01);
  EXPECT_EQ(json["runs"][0]["directions"]["sideways"].get<int>(), 1);
  EXPECT_DOUBLE_EQ(json["runs"][0]["mean_velocity_spread"]["vx"]["max"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(json["methods"]["diayn"]["survivors_both"].get<double>(), 1.0);
}

// Over seeds, each method's figures come with their spread: the sample standard deviation.
TEST(SkillReport, GivesEachMethodsSpreadOverItsSeeds) {
  std::vector<ReportRun> runs = TwoMethods();
  EXPECT_TRUE(ReportJson(runs)["methods"]["flsd"]["coverage_rate_std"].is_null());  // one seed: none
  ReportRun second = ::flsd::Run("flsd_s2", "flsd", {Moving(0, 600, 0.0, 0.0, 0.0, 2)}, {Moving(0, 600, 0.0, 0.0, 0.0, 2)});
  runs.push_back(second);
  const nlohmann::json flsd = ReportJson(runs)["methods"]["flsd"];
  const double a = runs[0].nominal.coverage.rate, b = second.nominal.coverage.rate;
  EXPECT_NEAR(flsd["coverage_rate"].get<double>(), (a + b) / 2, 1e-12);
  EXPECT_NEAR(flsd["coverage_rate_std"].get<double>(), std::abs(a - b) / std::sqrt(2.0), 1e-12);
  EXPECT_EQ(flsd["coverage_rate_per_run"].size(), 2u);
}

// The scaled reading: every run on one grid of the deviations pooled over all runs. Base heights
// (0.25, 0.26, 0.27 m by skill) pool to a deviation of 0.0075 m, so each skill is its own cell:
// DIAYN's two still skills fill two, FLSD's three movers three. HF medians of each method's runs.
TEST(SkillReport, ReadsCoverageOnThePooledScaledGridAndGivesMedians) {
  std::vector<ReportRun> runs = TwoMethods();
  runs.push_back(::flsd::Run("flsd_s2", "flsd", {Moving(0, 600, 0.0, 0.0, 0.0, 2)}, {Moving(0, 600, 0.0, 0.0, 0.0, 2)}));
  const nlohmann::json json = ReportJson(runs);
  std::vector<const std::vector<SkillTrajectory>*> all;
  for (const ReportRun& r : runs) all.push_back(&r.nominal.trajectories);
  const CoverageScales scales = PooledCoverageScales(all);
  for (int d = 0; d < kCoverageDims; ++d) EXPECT_DOUBLE_EQ(json["coverage_scales"][d].get<double>(), scales[d]);
  EXPECT_NEAR(scales[6], 0.0075, 1e-4);
  EXPECT_EQ(json["runs"][1]["scaled_coverage"]["cells_visited"], 2);
  EXPECT_EQ(json["runs"][1]["scaled_coverage"]["dim_cells"]["lin_vel_x"], 1);
  EXPECT_EQ(json["runs"][0]["scaled_coverage"]["cells_visited"], 3);
  EXPECT_EQ(json["runs"][0]["scaled_coverage"]["dim_cells"]["lin_vel_x"], 3);  // 0.5, -0.4 and 0 m/s
  EXPECT_EQ(json["runs"][2]["scaled_coverage"]["cells_visited"], 1);
  const nlohmann::json& c = json["comparison"];
  EXPECT_DOUBLE_EQ(c["scaled_coverage_ratio"].get<double>(), (3.0 + 1.0) / 2 / 2.0);
  EXPECT_EQ(c["scaled_coverage_ratio_per_flsd_run"], nlohmann::json({1.5, 0.5}));
  const double h1 = runs[0].nominal.high_frequency.pooled_ratio, h2 = runs[2].nominal.high_frequency.pooled_ratio;
  EXPECT_DOUBLE_EQ(json["methods"]["flsd"]["high_frequency_ratio_median"].get<double>(), (h1 + h2) / 2);
  EXPECT_DOUBLE_EQ(c["high_frequency_ratio_of_medians"].get<double>(),
                   (h1 + h2) / 2 / runs[1].nominal.high_frequency.pooled_ratio);
}

TEST(SkillReport, CountsSurvivorsWithinTheJointSpeedLimit) {
  std::vector<ReportRun> runs = TwoMethods();
  EXPECT_EQ(ReportJson(runs)["runs"][0]["survivors_within_joint_speed_limit"].get<int>(), 3);
  // Two samples of skill 1's joint 7 past the A1's 21 rad/s (0.04 s): skilld lets that pass.
  auto& points = runs[0].nominal.trajectories[1].points;
  points[300].joint_velocity[7] = -25.0;
  points[301].joint_velocity[7] = 22.0;
  ComputeMetrics(runs[0].nominal, kRate);
  EXPECT_DOUBLE_EQ(runs[0].nominal.skills[1].max_joint_speed, 25.0);
  EXPECT_EQ(ReportJson(runs)["runs"][0]["survivors_within_joint_speed_limit"].get<int>(), 3);
  // A third sample in a row (0.06 s) is where skilld would stop it.
  points[302].joint_velocity[7] = 21.5;
  ComputeMetrics(runs[0].nominal, kRate);
  EXPECT_EQ(ReportJson(runs)["runs"][0]["survivors_within_joint_speed_limit"].get<int>(), 2);
}

TEST(SkillReport, OneMethodHasNoComparison) {
  std::vector<ReportRun> runs = TwoMethods();
  runs.pop_back();
  EXPECT_FALSE(ReportJson(runs).contains("comparison"));
}

TEST(SkillReport, WritesThePageItsFiguresAndTheJson) {
  namespace fs = std::filesystem;
  const std::string dir = testutil::UniqueTempPath("report");
  WriteSkillReport(TwoMethods(), dir, "abc123");
  for (const char* name : {"index.html", "report.json", "coverage_flsd_s1.svg", "coverage_diayn_s1.svg",
                           "psd_flsd_s1.svg", "psd_diayn_s1.svg", "embedding.svg", "velocity_lateral.svg",
                           "velocity_yaw.svg"}) {
    EXPECT_TRUE(fs::exists(fs::path(dir) / name)) << name;
  }
  std::ifstream in(fs::path(dir) / "index.html");
  std::stringstream html;
  html << in.rdbuf();
  EXPECT_NE(html.str().find("abc123"), std::string::npos);
  EXPECT_NE(html.str().find("Table I"), std::string::npos);
  EXPECT_NE(html.str().find("src=\"embedding.svg\""), std::string::npos);
  const nlohmann::json json = nlohmann::json::parse(std::ifstream(fs::path(dir) / "report.json"));
  EXPECT_EQ(json["runs"].size(), 2u);
  fs::remove_all(dir);
}

TEST(SkillReport, RefusesNoRuns) {
  const std::string message = testutil::InputErrorMessage([] { WriteSkillReport({}, "/tmp/x", ""); });
  EXPECT_NE(message.find("no runs"), std::string::npos);
}

}  // namespace
}  // namespace flsd
