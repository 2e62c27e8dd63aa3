#include "skills/learning/tasks/selector_reward.h"

#include <cmath>


namespace flsd {

double SelectorRewardPerSecond(const SelectorRewardConfig& config, const Eigen::Vector3d& window_error,
                               const Eigen::Vector3d& error, double penalties_per_s) {
  const auto tracking = [&](const Eigen::Vector3d& e) {
    return std::exp(-e.cwiseProduct(Eigen::Vector3d(1.0, 1.0, config.turn_weight)).squaredNorm() / config.sigma);
  };
  return config.window_share * tracking(window_error) + (1.0 - config.window_share) * tracking(error) +
         config.penalty_scale * penalties_per_s;
}

}  // namespace flsd
