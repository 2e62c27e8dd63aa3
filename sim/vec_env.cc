#include "sim/vec_env.h"

#include "core/check.h"
#include "robot/observation.h"

namespace flsd {

VecEnv::VecEnv(const EnvConfig& config, int num_envs, uint64_t seed, int num_threads, int first_env)
    : model_(LoadMjModel(config.model)), pool_(num_threads), constraints_(config.constraints) {
  if (num_envs < 1) throw InputError("VecEnv: num_envs must be at least 1, got " + std::to_string(num_envs));
  envs_.reserve(num_envs);
  for (int i = 0; i < num_envs; ++i) envs_.emplace_back(*model_, config, StreamSeed(seed, first_env + i));
  motion_obs_.assign(num_envs * kMotionObsSize, 0.0f);
  terminal_motion_obs_.assign(num_envs * kMotionObsSize, 0.0f);
  position_.assign(num_envs * 3, 0.0f);
  terminal_position_.assign(num_envs * 3, 0.0f);
  foot_contact_.assign(num_envs * a1::kNumLegs, 0);
  termination_.assign(num_envs, Termination::kNone);
  stepped_calf_contact_.assign(num_envs, 0);
  violations_.assign(num_envs * kNumConstraints, 0.0f);
  terminal_state_.resize(num_envs);
  for (int i = 0; i < num_envs; ++i) WriteRow(i, &motion_obs_[i * kMotionObsSize], &position_[i * 3]);
}

void VecEnv::Reset() {
  pool_.ParallelFor(num_envs(), [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      envs_[i].Reset();
      termination_[i] = Termination::kNone;
      stepped_calf_contact_[i] = 0;
      WriteRow(i, &motion_obs_[i * kMotionObsSize], &position_[i * 3]);
    }
  });
}

void VecEnv::Step(const float* actions) {
  pool_.ParallelFor(num_envs(), [&](int begin, int end) {
    for (int i = begin; i < end; ++i) {
      Env& env = envs_[i];
      const Termination t = env.Step(actions + i * kActionSize);
      termination_[i] = t;
      stepped_calf_contact_[i] = env.calf_contact();
      if (constraints_.enabled) {
        const std::array<float, kNumConstraints> v = MeasureViolations(env, constraints_);
        std::copy(v.begin(), v.end(), &violations_[i * kNumConstraints]);
      }
      if (t != Termination::kNone) {
        WriteRow(i, &terminal_motion_obs_[i * kMotionObsSize], &terminal_position_[i * 3]);
        terminal_state_[i] = env.state();
        env.Reset();
      }
      WriteRow(i, &motion_obs_[i * kMotionObsSize], &position_[i * 3]);
    }
  });
}

void VecEnv::WriteRow(int i, float* motion_obs, float* position) {
  const RobotState& s = envs_[i].state();
  BuildMotionObservation(s, motion_obs);
  for (int k = 0; k < 3; ++k) position[k] = static_cast<float>(s.base_position[k]);
  for (int leg = 0; leg < a1::kNumLegs; ++leg) foot_contact_[i * a1::kNumLegs + leg] = s.foot_contact[leg];
}

}  // namespace flsd
