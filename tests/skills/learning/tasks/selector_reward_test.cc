// The semi-MDP selector's reward on a known case, the one that made per-step rewards pull the
// learned selectors toward the nearest skill: 0.5 m/s forward over walks at 0.41, 0.40 and 0.72
// m/s. Held 1 s each in a cycle, their 3-s mean is the command; the nearest walk alone is 0.09 m/s
// short at every step. Per step, legged_gym's reward pays the single walk more; the window's
// mean pays the cycle more.

#include "skills/learning/tasks/selector_reward.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "robot/a1.h"
#include "robot/observation.h"
#include "skills/runtime/selector_memory.h"

namespace flsd {
namespace {

// The reward (dt-scaled) over 9 s of forward speeds `holds` (m/s) each held 1 s in turn, after 3 s
// of the same to fill the window: what a selector that plays them is paid.
double RewardOfHolds(const SelectorRewardConfig& config, const std::vector<double>& holds) {
  const int hold_steps = 50, window = static_cast<int>(std::lround(config.window_s / a1::kControlDt));
  SelectorMemory memory(window);
  const double command[3] = {0.5, 0.0, 0.0};
  double total = 0.0;
  for (int t = 0; t < 12 * hold_steps; ++t) {
    const double v = holds[(t / hold_steps) % holds.size()];
    std::vector<float> motion(kMotionObsSize, 0.0f);
    motion[0] = static_cast<float>(v * kMotionObsLayout[0].scale);
    memory.Record(command, 0, motion.data());
    const double per_second = SelectorRewardPerSecond(config, memory.WindowError(), Eigen::Vector3d(0.5 - v, 0, 0), 0.0);
    if (t >= 3 * hold_steps) total += per_second * a1::kControlDt;
  }
  return total;
}

TEST(SelectorReward, PaysACycleWhoseMeanIsTheCommandMoreThanTheNearestSingleSkill) {
  SelectorRewardConfig config;
  config.window_s = 3.0;
  const std::vector<double> cycle = {0.41, 0.40, 0.72}, nearest = {0.41};
  EXPECT_GT(RewardOfHolds(config, cycle), RewardOfHolds(config, nearest) + 0.2);
  // All on the instantaneous velocity, as a per-step reward: the single walk wins.
  config.window_share = 0.0;
  EXPECT_LT(RewardOfHolds(config, cycle), RewardOfHolds(config, nearest));
}

TEST(SelectorReward, IsOneOnTheCommandAndAddsScaledPenaltiesAndWeighsTheYawRate) {
  SelectorRewardConfig config;
  config.penalty_scale = 0.5;
  EXPECT_DOUBLE_EQ(SelectorRewardPerSecond(config, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), -0.4), 0.8);
  // 0.2 rad/s off weighs as 0.1 m/s (NearestSkillSelector::kTurnWeight).
  const Eigen::Vector3d yaw(0, 0, 0.2), x(0.1, 0, 0);
  EXPECT_NEAR(SelectorRewardPerSecond(config, yaw, yaw, 0.0), SelectorRewardPerSecond(config, x, x, 0.0), 1e-12);
  EXPECT_NEAR(SelectorRewardPerSecond(config, x, x, 0.0), std::exp(-0.01 / 0.1), 1e-12);
}

}  // namespace
}  // namespace flsd
