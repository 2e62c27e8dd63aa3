#pragma once
// legged_gym's velocity-tracking environment over a VecEnv: each env holds a velocity command,
// redrawn every resampling_s and at every new episode, and earns the velocity-tracking reward for
// each control step. The skill selector and the from-scratch baseline of the paper's Fig. 8 train
// on this same environment; they differ only in what turns an observation into joint actions.

#include <Eigen/Core>

#include <vector>

#include "sim/vec_env.h"
#include "skills/learning/tasks/velocity_tracking.h"

namespace flsd {

struct VelocityEnvConfig {
  VelocityCommandConfig commands;
  VelocityRewardConfig reward;
  template <class V>
  void Visit(V& v) {
    v("commands", commands);
    v("reward", reward);
  }
};

class VelocityCommandEnv {
 public:
  static constexpr uint64_t kCommandStream = 7919;  // the command draws' seed offset from the run's seed

  // As VecEnv, a data-parallel rank holds envs [first_env, first_env + num_envs) of a larger batch
  // and draws the commands those envs would draw in one process.
  VelocityCommandEnv(const EnvConfig& env, const VelocityEnvConfig& config, int num_envs, uint64_t seed, int num_threads,
               int first_env = 0);

  int num_envs() const { return vec_.num_envs(); }
  VecEnv& vec_env() { return vec_; }
  const VecEnv& vec_env() const { return vec_; }

  // Steps every env with its row of joint actions (num_envs x 12). Ended episodes are reset with a
  // fresh command; commands are redrawn on their schedule.
  void Step(const float* actions);

  // Per env: the command now, (vx, vy, wz) body frame.
  const Eigen::Vector3d& command(int i) const { return command_[i]; }
  // Writes every env's o^c (robot/observation.h) into out (num_envs x kTaskObsSize).
  void WriteTaskObservations(float* out) const;
  // Of the last Step, per env: the reward (dt-scaled, clipped at 0) and its terms.
  const std::vector<float>& rewards() const { return rewards_; }
  const VelocityRewardTerms& terms(int i) const { return terms_[i]; }
  // The per-env command streams, for checkpoints.
  std::vector<Rng>& command_rngs() { return command_rng_; }
  const std::vector<Rng>& command_rngs() const { return command_rng_; }

 private:
  void NewCommand(int i);

  VelocityEnvConfig config_;
  VecEnv vec_;
  int resampling_steps_;
  std::vector<Rng> command_rng_;
  std::vector<Eigen::Vector3d> command_;
  std::vector<int> steps_since_command_;
  std::vector<VelocityTrackingReward> reward_;
  std::vector<VelocityRewardTerms> terms_;
  std::vector<float> rewards_;
};

}  // namespace flsd
