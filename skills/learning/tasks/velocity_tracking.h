#pragma once
// legged_gym's velocity-tracking task, the reward that the skill selector (Sec. IV-C) and the
// from-scratch baseline of the paper's Fig. 8 are trained on: velocity commands drawn from fixed
// ranges and resampled, and the reward terms and scales of legged_gym's A1 configuration
// (legged_gym's a1_config.py and legged_robot_config.py, rewards and commands). Each term is
// scaled by dt and the total is clipped at zero (only_positive_rewards), as in legged_gym.

#include <Eigen/Core>

#include <array>
#include <vector>

#include "core/config.h"
#include "core/rng.h"
#include "robot/robot_state.h"

namespace flsd {

struct VelocityCommandConfig {
  Interval vx{-1.0, 1.0};  // m/s, body frame
  Interval vy{-1.0, 1.0};  // m/s
  Interval wz{-1.0, 1.0};  // rad/s
  double resampling_s = 10.0;
  double min_planar_speed = 0.2;  // commands slower than this in xy are zeroed
  double zero_share = 0.0;        // share of commands that are "stand still"
  // A new selector run sets vx, vy and wz to the range of its library's surviving skills'
  // velocities, widened by this factor (0: keep the ranges given): commands it can follow.
  double library_envelope = 0.0;
  // A share of the commands is drawn near what some skill does: one of skill_velocities (flat
  // (vx, vy, wz) triples), uniformly, plus uniform noise within +-skill_noise on each axis. A new
  // selector run with skill_share > 0 and no skill_velocities fills them from its library's
  // dependable skills, so that it learns where its skills can follow (the uniform box is mostly
  // combinations none can); given ones (another library's, for a comparison on one task) are kept.
  double skill_share = 0.0;
  std::vector<double> skill_noise{0.2, 0.2, 0.4};  // m/s, m/s, rad/s
  std::vector<double> skill_velocities;
  template <class V>
  void Visit(V& v) {
    v("vx", vx, Bounds<double>{-5.0, 5.0});
    v("vy", vy, Bounds<double>{-5.0, 5.0});
    v("wz", wz, Bounds<double>{-10.0, 10.0});
    v("resampling_s", resampling_s, Bounds<double>{0.02, 3600.0});
    v("min_planar_speed", min_planar_speed, Bounds<double>{0.0, 5.0});
    v("zero_share", zero_share, Bounds<double>{0.0, 1.0});
    v("library_envelope", library_envelope, Bounds<double>{0.0, 10.0});
    v("skill_share", skill_share, Bounds<double>{0.0, 1.0});
    v("skill_noise", skill_noise, Bounds<double>{0.0, 10.0});
    v("skill_velocities", skill_velocities, Bounds<double>{-10.0, 10.0});
  }
};

// Zero with probability zero_share; else near a skill's velocity with probability skill_share; else
// (vx, vy, wz) each uniform in its range. xy is zeroed below min_planar_speed. With skill_share,
// config must pass ValidateSkillCommands.
Eigen::Vector3d SampleVelocityCommand(Rng& rng, const VelocityCommandConfig& config);
// InputError unless skill_share is 0 or skill_velocities holds (vx, vy, wz) triples and skill_noise 3 values.
void ValidateSkillCommands(const VelocityCommandConfig& config);

// Calls f(name, a.term, b.term) for every reward term (not the total) of a and b, which may be
// VelocityRewardTerms or VelocityRewardConfig: the one list of terms for whatever pairs them up.
template <class A, class B, class F>
void ForEachTerm(A& a, B& b, F f) {
  f("tracking_lin_vel", a.tracking_lin_vel, b.tracking_lin_vel);
  f("tracking_ang_vel", a.tracking_ang_vel, b.tracking_ang_vel);
  f("lin_vel_z", a.lin_vel_z, b.lin_vel_z);
  f("ang_vel_xy", a.ang_vel_xy, b.ang_vel_xy);
  f("orientation", a.orientation, b.orientation);
  f("torques", a.torques, b.torques);
  f("dof_acc", a.dof_acc, b.dof_acc);
  f("feet_air_time", a.feet_air_time, b.feet_air_time);
  f("collision", a.collision, b.collision);
  f("action_rate", a.action_rate, b.action_rate);
  f("dof_pos_limits", a.dof_pos_limits, b.dof_pos_limits);
}

struct VelocityRewardConfig {
  double tracking_sigma = 0.25;
  double tracking_lin_vel = 1.0;
  double tracking_ang_vel = 0.5;
  double lin_vel_z = -2.0;
  double ang_vel_xy = -0.05;
  double orientation = 0.0;
  double torques = -2e-4;  // the A1's
  double dof_acc = -2.5e-7;
  double feet_air_time = 1.0;
  double collision = -1.0;
  double action_rate = -0.01;
  double dof_pos_limits = -10.0;  // the A1's
  double soft_dof_pos_limit = 0.9;
  double feet_air_time_target = 0.5;  // s
  template <class V>
  void Visit(V& v) {
    v("tracking_sigma", tracking_sigma, Bounds<double>{1e-4, 100.0});
    ForEachTerm(*this, *this, [&](const char* name, double& scale, double&) { v(name, scale, Bounds<double>{-1e6, 1e6}); });
    v("soft_dof_pos_limit", soft_dof_pos_limit, Bounds<double>{0.1, 1.0});
    v("feet_air_time_target", feet_air_time_target, Bounds<double>{0.0, 5.0});
  }
};

// The terms of one control step, unscaled by dt (for logging), and their scaled, clipped total.
struct VelocityRewardTerms {
  double tracking_lin_vel = 0, tracking_ang_vel = 0, lin_vel_z = 0, ang_vel_xy = 0, orientation = 0, torques = 0,
         dof_acc = 0, feet_air_time = 0, collision = 0, action_rate = 0, dof_pos_limits = 0;
  double total = 0;  // sum of scale * term * dt, clipped at 0
};

// Each term times its scale, and `total` their unclipped sum: the reward per second the terms pay.
VelocityRewardTerms Scaled(const VelocityRewardTerms& terms, const VelocityRewardConfig& config);

// The reward of one environment; it carries what the terms need from the previous step.
class VelocityTrackingReward {
 public:
  explicit VelocityTrackingReward(const VelocityRewardConfig& config) : config_(config) {}

  // Starts an episode at `state`.
  void Reset(const RobotState& state);

  // The reward for the step that ended in `state`, under `command` (vx, vy, wz), with joint
  // action `action` (12), and whether a calf or thigh touched the ground (a collision).
  VelocityRewardTerms Step(const RobotState& state, const Eigen::Vector3d& command, const float* action,
                           bool collision);

 private:
  VelocityRewardConfig config_;
  a1::JointArray<double> previous_joint_velocity_{};
  a1::JointArray<float> previous_action_{};
  std::array<double, a1::kNumLegs> air_time_{};
  std::array<bool, a1::kNumLegs> previous_contact_{};
};

}  // namespace flsd
