#include "robot/observation.h"

#include <algorithm>
#include <string>

#include "core/check.h"

namespace flsd {
namespace {

constexpr double Scale(int segment) { return kMotionObsLayout[segment].scale; }

}  // namespace

void BuildMotionObservation(const RobotState& state, float* out) {
  const Eigen::Vector3d gravity = state.ProjectedGravity();
  for (int i = 0; i < 3; ++i) {
    out[0 + i] = static_cast<float>(Scale(0) * state.base_linear_velocity[i]);
    out[3 + i] = static_cast<float>(Scale(1) * state.base_angular_velocity[i]);
    out[6 + i] = static_cast<float>(Scale(2) * gravity[i]);
  }
  for (int j = 0; j < a1::kNumJoints; ++j) {
    out[9 + j] = static_cast<float>(Scale(3) * (state.joint_position[j] - a1::kDefaultJointPos[j]));
    out[21 + j] = static_cast<float>(Scale(4) * state.joint_velocity[j]);
  }
}

void BuildPolicyObservation(const float* motion_obs, const float* previous_action, int skill,
                            int num_skills, float* out) {
  if (skill < 0 || skill >= num_skills) {
    throw InputError("skill " + std::to_string(skill) + " is out of range: the library has " +
                     std::to_string(num_skills) + " skills (0.." + std::to_string(num_skills - 1) +
                     ")");
  }
  std::copy(motion_obs, motion_obs + kMotionObsSize, out);
  std::copy(previous_action, previous_action + kActionSize, out + kMotionObsSize);
  float* onehot = out + kMotionObsSize + kActionSize;
  std::fill(onehot, onehot + num_skills, 0.0f);
  onehot[skill] = 1.0f;
}

void BuildTaskObservation(const float* motion_obs, const double* command, float* out) {
  std::copy(motion_obs, motion_obs + kMotionObsSize, out);
  out[kMotionObsSize + 0] = static_cast<float>(Scale(0) * command[0]);
  out[kMotionObsSize + 1] = static_cast<float>(Scale(0) * command[1]);
  out[kMotionObsSize + 2] = static_cast<float>(Scale(1) * command[2]);
}

a1::JointArray<double> JointTargetsFromAction(const float* action) {
  a1::JointArray<double> target;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    const double a = std::clamp(static_cast<double>(action[j]), -a1::kActionClip, a1::kActionClip);
    target[j] = a1::kDefaultJointPos[j] + a1::kActionScale * a;
  }
  return target;
}

}  // namespace flsd
