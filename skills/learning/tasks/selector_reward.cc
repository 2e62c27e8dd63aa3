#include "skills/learning/tasks/selector_reward.h"

#include <cmath>

#include "skills/runtime/nearest_skill.h"

namespace flsd {

double SelectorRewardPerSecond(const SelectorRewardConfig& config, const Eigen::Vector3d& window_error,
                               const Eigen::Vector3d& error, double penalties_per_s) {
  const auto tracking = [&](const Eigen::Vector3d& e) {
    return std::exp(-NearestSkillSelector::SquaredDistance(e, Eigen::Vector3d::Zero()) / config.sigma);
  };
  return config.window_share * tracking(window_error) + (1.0 - config.window_share) * tracking(error) +
         config.penalty_scale * penalties_per_s;
}

}  // namespace flsd
