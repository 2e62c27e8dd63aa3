#include "skills/learning/tasks/velocity_command_env.h"

#include <algorithm>
#include <cmath>

#include "robot/observation.h"

namespace flsd {

VelocityCommandEnv::VelocityCommandEnv(const EnvConfig& env, const VelocityEnvConfig& config, int num_envs, uint64_t seed,
                           int num_threads, int first_env)
    : config_(config),
      vec_(env, num_envs, seed, num_threads, first_env),
      resampling_steps_(std::max(1, static_cast<int>(std::lround(config.commands.resampling_s / a1::kControlDt)))),
      command_(num_envs, Eigen::Vector3d::Zero()),
      steps_since_command_(num_envs, 0),
      reward_(num_envs, VelocityTrackingReward(config.reward)),
      terms_(num_envs),
      rewards_(num_envs, 0.0f) {
  ValidateSkillCommands(config.commands);
  for (int i = 0; i < num_envs; ++i) {
    command_rng_.emplace_back(StreamSeed(seed + kCommandStream, first_env + i));
    NewCommand(i);
    reward_[i].Reset(vec_.env(i).state());
  }
}

void VelocityCommandEnv::NewCommand(int i) {
  command_[i] = SampleVelocityCommand(command_rng_[i], config_.commands);
  steps_since_command_[i] = 0;
}

void VelocityCommandEnv::Step(const float* actions) {
  vec_.Step(actions);
  vec_.pool().ParallelFor(num_envs(), [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      terms_[i] = reward_[i].Step(vec_.stepped_state(i), command_[i], actions + i * kActionSize,
                                  vec_.stepped_calf_contact(i));
      rewards_[i] = static_cast<float>(terms_[i].total);
      if (vec_.termination()[i] != Termination::kNone) {
        NewCommand(i);
        reward_[i].Reset(vec_.env(i).state());
      } else if (++steps_since_command_[i] >= resampling_steps_) {
        NewCommand(i);
      }
    }
  });
}

void VelocityCommandEnv::WriteTaskObservations(float* out) const {
  for (int i = 0; i < num_envs(); ++i) {
    BuildTaskObservation(vec_.motion_obs() + i * kMotionObsSize, command_[i].data(), out + i * kTaskObsSize);
  }
}

}  // namespace flsd
