#include "skills/learning/tasks/smoothness.h"

#include <cmath>

#include "robot/a1.h"

namespace flsd {

double ActionRate(const float* action, const float* previous_action) {
  double sum = 0.0;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    sum += std::pow(static_cast<double>(previous_action[j]) - action[j], 2);
  }
  return sum;
}

double JointAcceleration(const double* joint_velocity, const double* previous_joint_velocity) {
  double sum = 0.0;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    sum += std::pow((previous_joint_velocity[j] - joint_velocity[j]) / a1::kControlDt, 2);
  }
  return sum;
}

}  // namespace flsd
