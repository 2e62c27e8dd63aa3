#pragma once
// legged_gym's smoothness terms, unscaled, shared by every task that pays for them: the action
// rate |a_t - a_{t-1}|^2 and the joint acceleration |(qdot_t - qdot_{t-1}) / dt|^2 over the 12
// joints, dt the control step.

namespace flsd {

double ActionRate(const float* action, const float* previous_action);
double JointAcceleration(const double* joint_velocity, const double* previous_joint_velocity);

}  // namespace flsd
