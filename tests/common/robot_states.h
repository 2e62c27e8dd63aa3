#pragma once
// Robot states the limit tests start from: the A1 standing in its default pose, and the same
// robot turned about one body axis.

#include <Eigen/Geometry>

#include "robot/a1.h"
#include "robot/robot_state.h"

namespace flsd::testutil {

inline RobotState Standing() {
  RobotState s;
  s.base_position = {0.0, 0.0, 0.27};
  s.joint_position = a1::kDefaultJointPos;
  return s;
}

// Standing, turned by `angle` rad about `axis`: about x it rolls, about y it pitches.
inline RobotState Turned(const Eigen::Vector3d& axis, double angle) {
  RobotState s = Standing();
  s.base_orientation = Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis));
  return s;
}

}  // namespace flsd::testutil
