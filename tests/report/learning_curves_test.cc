// Learning curves from progress.csv files: a column read back, the mean and spread over seeds,
// and a chart of several seeds drawn as their mean and a band.

#include "report/learning_curves.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

std::string WriteCsv(const std::string& name, const std::string& text) {
  const std::string path = testutil::UniqueTempPath(name);
  std::ofstream(path) << text;
  return path;
}

TEST(LearningCurves, ReadsAColumnAndNamesTheFileAndColumnItLacks) {
  const std::string csv = WriteCsv("a.csv", "iteration,env_steps,mean_reward\n1,100,0.5\n2,200,0.25\n");
  EXPECT_THAT(ReadCsvColumn(csv, "mean_reward"), ElementsAre(0.5, 0.25));
  const std::string message = testutil::InputErrorMessage([&] { ReadCsvColumn(csv, "reward"); });
  EXPECT_THAT(message, HasSubstr(csv + ": no column 'reward'; the columns are iteration,env_steps,mean_reward"));
}

TEST(LearningCurves, TheSpreadOverSeedsIsTheirMeanLowestAndHighestRowByRow) {
  const SeedSpread s = SpreadOverSeeds({{1.0, 2.0, 3.0}, {3.0, 0.0, 6.0, 9.0}, {2.0, 1.0, 0.0}});
  EXPECT_THAT(s.mean, ElementsAre(2.0, 1.0, 3.0));  // three rows: the shortest seed's
  EXPECT_THAT(s.low, ElementsAre(1.0, 0.0, 0.0));
  EXPECT_THAT(s.high, ElementsAre(3.0, 2.0, 6.0));
}

TEST(LearningCurves, SeveralSeedsAreDrawnAsTheirMeanAndABand) {
  const std::string a = WriteCsv("s1.csv", "env_steps,mean_reward\n100,0.0\n200,1.0\n");
  const std::string b = WriteCsv("s2.csv", "env_steps,mean_reward\n100,2.0\n200,3.0\n");
  CurvePlotOptions options;
  options.output = testutil::UniqueTempPath("curves.svg");
  PlotCurves({{"FLSD-L", {a, b}}, {"Scratch", {a}}}, options);
  std::stringstream svg;
  svg << std::ifstream(options.output).rdbuf();
  EXPECT_THAT(svg.str(), HasSubstr("FLSD-L (mean of 2 seeds)"));
  EXPECT_THAT(svg.str(), HasSubstr("<polygon"));  // one band, for the curve with two seeds
  EXPECT_EQ(svg.str().find("<polygon"), svg.str().rfind("<polygon"));
  EXPECT_THAT(svg.str(), HasSubstr(">Scratch<"));  // one seed: no band, no "mean of"
  EXPECT_THAT(svg.str(), ::testing::Not(HasSubstr("Scratch (mean")));
}

TEST(LearningCurves, SeedsThatDoNotShareTheirXColumnAreRefusedNamingTheFile) {
  const std::string a = WriteCsv("x1.csv", "env_steps,mean_reward\n100,0.0\n200,1.0\n");
  const std::string b = WriteCsv("x2.csv", "env_steps,mean_reward\n100,2.0\n400,3.0\n");
  CurvePlotOptions options;
  options.output = testutil::UniqueTempPath("mismatch.svg");
  const std::string message = testutil::InputErrorMessage([&] { PlotCurves({{"FLSD-L", {a, b}}}, options); });
  EXPECT_THAT(message, HasSubstr(b + ": row 3 has env_steps 400"));
  EXPECT_THAT(message, HasSubstr("seeds of 'FLSD-L' must share their env_steps column"));
}

}  // namespace
}  // namespace flsd
