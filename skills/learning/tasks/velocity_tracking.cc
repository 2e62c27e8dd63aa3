#include "skills/learning/tasks/velocity_tracking.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/check.h"
#include "skills/learning/tasks/smoothness.h"

namespace flsd {

Eigen::Vector3d SampleVelocityCommand(Rng& rng, const VelocityCommandConfig& config) {
  // Drawn only when asked for, so that configs without zero commands keep their random streams.
  if (config.zero_share > 0.0 && Uniform(rng, 0.0, 1.0) < config.zero_share) return Eigen::Vector3d::Zero();
  Eigen::Vector3d command;
  if (config.skill_share > 0.0 && Uniform(rng, 0.0, 1.0) < config.skill_share) {
    const std::vector<double>& v = config.skill_velocities;  // validated: triples, at least one
    const size_t skill = std::min(v.size() / 3 - 1, static_cast<size_t>(Uniform(rng, 0.0, v.size() / 3.0)));
    for (int a = 0; a < 3; ++a) {
      command[a] = v[3 * skill + a] + Uniform(rng, -config.skill_noise[a], config.skill_noise[a]);
    }
  } else {
    command = {Uniform(rng, config.vx.lo, config.vx.hi), Uniform(rng, config.vy.lo, config.vy.hi),
               Uniform(rng, config.wz.lo, config.wz.hi)};
  }
  if (command.head<2>().norm() < config.min_planar_speed) command.head<2>().setZero();
  return command;
}

void ValidateSkillCommands(const VelocityCommandConfig& config) {
  const size_t n = config.skill_velocities.size();
  if (config.skill_share > 0.0 && (n == 0 || n % 3 != 0 || config.skill_noise.size() != 3)) {
    throw InputError("task.commands: skill_share needs skill_velocities as (vx, vy, wz) triples (a new selector run "
                     "takes them from its library) and skill_noise of 3 values; got " + std::to_string(n) + " and " +
                     std::to_string(config.skill_noise.size()) + " values");
  }
}

void VelocityTrackingReward::Reset(const RobotState& state) {
  previous_joint_velocity_ = state.joint_velocity;
  previous_action_.fill(0.0f);
  air_time_.fill(0.0);
  previous_contact_ = state.foot_contact;
}

VelocityRewardTerms VelocityTrackingReward::Step(const RobotState& s, const Eigen::Vector3d& command,
                                                 const float* action, bool collision) {
  const double dt = a1::kControlDt;
  VelocityRewardTerms t;
  const Eigen::Vector3d& v = s.base_linear_velocity;
  const Eigen::Vector3d& w = s.base_angular_velocity;
  t.tracking_lin_vel = std::exp(-(command.head<2>() - v.head<2>()).squaredNorm() / config_.tracking_sigma);
  t.tracking_ang_vel = std::exp(-std::pow(command.z() - w.z(), 2) / config_.tracking_sigma);
  t.lin_vel_z = v.z() * v.z();
  t.ang_vel_xy = w.head<2>().squaredNorm();
  t.orientation = s.ProjectedGravity().head<2>().squaredNorm();
  for (int j = 0; j < a1::kNumJoints; ++j) {
    t.torques += s.joint_torque[j] * s.joint_torque[j];
    // Soft limits: the middle soft_dof_pos_limit of each joint's range.
    const double middle = 0.5 * (a1::JointMin(j) + a1::JointMax(j));
    const double half = 0.5 * (a1::JointMax(j) - a1::JointMin(j)) * config_.soft_dof_pos_limit;
    t.dof_pos_limits += std::max(0.0, (middle - half) - s.joint_position[j]) +
                        std::max(0.0, s.joint_position[j] - (middle + half));
  }
  t.dof_acc = JointAcceleration(s.joint_velocity.data(), previous_joint_velocity_.data());
  t.action_rate = ActionRate(action, previous_action_.data());
  previous_joint_velocity_ = s.joint_velocity;
  std::copy(action, action + a1::kNumJoints, previous_action_.begin());
  // Feet air time: rewarded at touchdown, for steps longer than the target, only while moving.
  for (int leg = 0; leg < a1::kNumLegs; ++leg) {
    const bool contact = s.foot_contact[leg] || previous_contact_[leg];  // legged_gym's filter
    const bool first_contact = air_time_[leg] > 0.0 && contact;  // it was in the air until now
    air_time_[leg] += dt;
    if (first_contact) t.feet_air_time += air_time_[leg] - config_.feet_air_time_target;
    if (contact) air_time_[leg] = 0.0;
    previous_contact_[leg] = s.foot_contact[leg];
  }
  if (command.head<2>().norm() <= 0.1) t.feet_air_time = 0.0;
  t.collision = collision ? 1.0 : 0.0;

  t.total = std::max(0.0, Scaled(t, config_).total * dt);
  return t;
}

VelocityRewardTerms Scaled(const VelocityRewardTerms& terms, const VelocityRewardConfig& config) {
  VelocityRewardTerms scaled = terms;
  scaled.total = 0.0;
  ForEachTerm(scaled, config, [&](const char*, double& term, double scale) {
    term *= scale;
    scaled.total += term;
  });
  return scaled;
}

}  // namespace flsd
