#pragma once
// The real A1 measures no base velocity or position, yet the policy needs v and navigation needs
// position. This Kalman filter estimates both in the world frame from what it does measure: the
// IMU's attitude, rate and specific force drive the prediction, and every foot in stance gives a
// measurement, since a foot that does not slip makes the base velocity -R (J qdot + w x r) and
// the base height (foot radius) - (R r)_z, with r and J from the URDF's leg kinematics.
// Horizontal position is integrated, not observed: it drifts with distance walked.

#include <Eigen/Core>

#include "hw/hw_config.h"
#include "hw/a1_protocol.h"
#include "hw/leg_kinematics.h"
#include "robot/robot_state.h"

namespace flsd::hw {


class StateEstimator {
 public:
  StateEstimator(LegKinematics kinematics, const EstimatorConfig& config);

  // Starts over at `position` (world frame), at rest.
  void Reset(const Eigen::Vector3d& position);

  // Folds in one state frame, `dt` seconds after the previous one.
  void Update(const LowState& frame, double dt);

  // The estimate, with the frame's own measurements (attitude, rates, joints, feet).
  const RobotState& state() const { return state_; }

 private:
  using Vector6d = Eigen::Matrix<double, 6, 1>;
  using Matrix6d = Eigen::Matrix<double, 6, 6>;

  LegKinematics kinematics_;
  EstimatorConfig config_;
  Vector6d x_ = Vector6d::Zero();  // world position, world velocity
  Matrix6d p_ = Matrix6d::Identity();
  RobotState state_;
  Eigen::Vector3d last_good_position_ = Eigen::Vector3d::Zero();
  double height_untrusted_time_ = 0.0;  // s with feet in stance, none of them within the height gate
};

}  // namespace flsd::hw
