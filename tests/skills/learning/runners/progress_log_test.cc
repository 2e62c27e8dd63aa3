// progress.csv: the header and each row come from one list of columns, the header is the one the
// committed runs were written with, and a resumed run drops the rows past its checkpoint.

#include "skills/learning/runners/progress_log.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "skills/learning/tasks/skill_discovery_task.h"
#include "skills/learning/tasks/velocity_tracking_task.h"
#include "tests/common/test_support.h"

namespace flsd {
namespace {

int Columns(const std::string& line) { return 1 + static_cast<int>(std::count(line.begin(), line.end(), ',')); }

// The columns every skill run in runs/ before the travel term was written with: readers (flsd
// report, the plots) rely on them. Later runs add travel_reward at the end, so the older columns
// keep their places.
constexpr const char* kCommittedHeader =
    "iteration,env_steps,steps_per_s,episodes_ended,mean_episode_length,fall_fraction,discriminator_accuracy,"
    "intrinsic_reward,discriminator_loss,pae_loss,surrogate_loss,value_loss,entropy,kl,learning_rate,action_std,"
    "seconds_physics,seconds_policy,seconds_bookkeeping,seconds_reward,seconds_ppo,seconds_pae,"
    "seconds_discriminator,seconds_total,regularization,termination_probability,violation_foot_slip,"
    "violation_low_base_moving,violation_joint_speed,violation_joint_range,violation_calf_contact";

TEST(SkillProgress, HeaderIsTheCommittedRunsAndEachRowFillsIt) {
  RunnerStats runner;
  runner.iteration = 12;
  runner.env_steps = 73728;
  runner.ppo.learning_rate = 3.38e-05;
  SkillDiscoveryStats task;
  task.fall_fraction = 0.125;
  task.constraints.violation_rate[0] = 0.5;
  const ProgressRecord record = SkillProgress(runner, task);
  EXPECT_EQ(record.header(), std::string(kCommittedHeader) + ",travel_reward");
  EXPECT_EQ(Columns(record.row()), Columns(record.header()));
  EXPECT_EQ(record.row().substr(0, 9), "12,73728,");
  EXPECT_NE(record.row().find(",0.1250,"), std::string::npos);   // fall_fraction, %.4f
  EXPECT_NE(record.row().find(",3.38e-05,"), std::string::npos);  // learning_rate, %.3g
}

TEST(VelocityProgress, EachRowFillsTheHeader) {
  RunnerStats runner;
  runner.iteration = 3;
  VelocityTrackingStats task;
  task.zero_reward_share = 0.25;
  runner.ppo.prior_kl = 0.125;
  const ProgressRecord record = VelocityProgress(runner, task, 0.5);
  EXPECT_EQ(record.header().rfind("iteration,env_steps,steps_per_s,mean_reward,", 0), 0u);
  EXPECT_EQ(record.header().substr(record.header().rfind(",zero_reward_share")), ",zero_reward_share,prior_kl");
  EXPECT_EQ(Columns(record.row()), Columns(record.header()));
  EXPECT_EQ(record.row().substr(record.row().rfind(",0.2500,")), ",0.2500,0.12500");
}

TEST(ProgressLog, AResumedRunDropsTheRowsPastItsCheckpoint) {
  const testutil::ScratchFile file(".csv");
  const std::string header = SkillProgress(RunnerStats{}, SkillDiscoveryStats{}).header();
  {
    ProgressLog log(file.path(), header, 0);
    for (int i = 1; i <= 5; ++i) {
      RunnerStats s;
      s.iteration = i;
      log.Append(SkillProgress(s, SkillDiscoveryStats{}).row());
    }
  }
  ProgressLog resumed(file.path(), header, 3);  // the checkpoint was at iteration 3
  std::ifstream in(file.path());
  std::string line;
  std::vector<int> iterations;
  std::getline(in, line);
  EXPECT_EQ(line, header);
  while (std::getline(in, line)) iterations.push_back(std::stoi(line.substr(0, line.find(','))));
  EXPECT_EQ(iterations, (std::vector<int>{1, 2, 3}));
}

}  // namespace
}  // namespace flsd
