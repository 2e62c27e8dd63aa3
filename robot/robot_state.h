#pragma once
#include <Eigen/Geometry>

#include <cmath>

#include "robot/a1.h"

namespace flsd {

// Heading (rad): the rotation about the world z axis of the body's x axis.
inline double YawOf(const Eigen::Quaterniond& q) {
  return std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()), 1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
}

// What a backend measures (or, on the robot, estimates) at one control tick.
struct RobotState {
  double time = 0.0;  // s since the backend started
  Eigen::Vector3d base_position = Eigen::Vector3d::Zero();  // world frame, m
  Eigen::Quaterniond base_orientation = Eigen::Quaterniond::Identity();  // body to world
  Eigen::Vector3d base_linear_velocity = Eigen::Vector3d::Zero();   // body frame, m/s
  Eigen::Vector3d base_angular_velocity = Eigen::Vector3d::Zero();  // body frame, rad/s
  a1::JointArray<double> joint_position{};  // rad, a1::kJointNames order
  a1::JointArray<double> joint_velocity{};  // rad/s
  a1::JointArray<double> joint_torque{};    // N m, last applied
  std::array<bool, a1::kNumLegs> foot_contact{};     // FR, FL, RR, RL
  std::array<double, a1::kNumLegs> foot_force{};     // contact normal force, N

  // Gravity direction (0, 0, -1) seen in the body frame.
  Eigen::Vector3d ProjectedGravity() const {
    return base_orientation.conjugate() * Eigen::Vector3d(0.0, 0.0, -1.0);
  }
  double Yaw() const { return YawOf(base_orientation); }
};

// A motor-level command, as the A1's motor drivers take it:
// tau = kp (position - q) + kd (velocity - qdot) + torque, clipped to the torque limit.
struct JointCommand {
  a1::JointArray<double> position{};
  a1::JointArray<double> velocity{};
  a1::JointArray<double> kp{};
  a1::JointArray<double> kd{};
  a1::JointArray<double> torque{};

  // PD about `target` with the training gains.
  static JointCommand Track(const a1::JointArray<double>& target) {
    JointCommand c;
    c.position = target;
    c.kp.fill(a1::kKp);
    c.kd.fill(a1::kKd);
    return c;
  }
  // Pure damping: no position stiffness, so the robot sinks slowly instead of being driven.
  static JointCommand Damp(double kd) {
    JointCommand c;
    c.kd.fill(kd);
    return c;
  }
};

// The most torque a motor turning at qd can give in qd's direction. A current-limited motor gives
// its full torque up to a knee speed; past it, back EMF against the supply voltage takes the
// torque away linearly, to nothing at a1::kJointVelocityLimit (the URDF's 21 rad/s, taken as the
// no-load speed). `knee` 0 is a line from rest. Torque against the motion (braking) keeps the
// full limit.
inline double DrivingTorqueLimit(double qd, double knee = 0.0) {
  const double speed = qd < 0.0 ? -qd : qd;
  if (speed <= knee) return a1::kTorqueLimit;
  if (speed >= a1::kJointVelocityLimit) return 0.0;
  return a1::kTorqueLimit * (a1::kJointVelocityLimit - speed) / (a1::kJointVelocityLimit - knee);
}

// The motor PD law for one joint, as the sim applies it at every physics step. `strength`
// scales the motor (domain randomisation); the result is clipped to +-a1::kTorqueLimit and, when
// `torque_speed_limit` is set, to DrivingTorqueLimit in the direction of motion, so the joint
// cannot drive itself past the motor's speed.
inline double MotorTorque(double kp, double kd, double q_target, double qd_target, double q,
                          double qd, double tau_ff, double strength = 1.0, bool torque_speed_limit = false,
                          double torque_speed_knee = 0.0) {
  const double tau = strength * (kp * (q_target - q) + kd * (qd_target - qd) + tau_ff);
  double lo = -a1::kTorqueLimit, hi = a1::kTorqueLimit;
  if (torque_speed_limit && qd > 0.0) hi = DrivingTorqueLimit(qd, torque_speed_knee);
  if (torque_speed_limit && qd < 0.0) lo = -DrivingTorqueLimit(qd, torque_speed_knee);
  return tau > hi ? hi : (tau < lo ? lo : tau);
}

}  // namespace flsd
