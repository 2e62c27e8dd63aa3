#pragma once
// The real A1 measures no base velocity or position, yet the policy needs v and navigation needs
// position. This Kalman filter estimates both in the world frame from what it does measure: the
// IMU's attitude, rate and specific force drive the prediction, and every foot in stance gives a
// measurement, since a foot that does not slip makes the base velocity -R (J qdot + w x r) and
// the base height (foot radius) - (R r)_z, with r and J from the URDF's leg kinematics.
// Horizontal position is integrated, not observed: it drifts with distance walked.

#include <Eigen/Core>

#include "core/config.h"
#include "hw/a1_protocol.h"
#include "hw/leg_kinematics.h"
#include "robot/robot_state.h"

namespace flsd::hw {

struct EstimatorConfig {
  double contact_threshold = 20.0;  // foot force above which a foot is in stance (sensor units)
  double accelerometer_noise = 1.0;  // m/s^2, drives the process noise
  double leg_velocity_noise = 0.05;  // m/s, per stance foot
  double leg_height_noise = 0.01;    // m, per stance foot
  // A foot whose squared Mahalanobis distance (4 degrees of freedom: velocity and height) is above
  // this slips. 9 keeps 94 % of feet that do not slip (chi-square); tuned on the shipped skills.
  double slip_gate = 9.0;
  template <class V>
  void Visit(V& v) {
    v("contact_threshold", contact_threshold, Bounds<double>{0.0, 10000.0});
    v("accelerometer_noise", accelerometer_noise, Bounds<double>{1e-4, 100.0});
    v("leg_velocity_noise", leg_velocity_noise, Bounds<double>{1e-4, 10.0});
    v("leg_height_noise", leg_height_noise, Bounds<double>{1e-5, 1.0});
    v("slip_gate", slip_gate, Bounds<double>{0.5, 10000.0});
  }
};

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
};

}  // namespace flsd::hw
