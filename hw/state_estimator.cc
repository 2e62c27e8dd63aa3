#include "hw/state_estimator.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

namespace flsd::hw {
namespace {

constexpr double kGravity = 9.81;

}  // namespace

StateEstimator::StateEstimator(LegKinematics kinematics, const EstimatorConfig& config)
    : kinematics_(std::move(kinematics)), config_(config) {
  Reset(Eigen::Vector3d(0.0, 0.0, 0.0));
}

void StateEstimator::Reset(const Eigen::Vector3d& position) {
  x_.setZero();
  x_.head<3>() = position;
  p_ = Matrix6d::Identity() * 1e-2;
  last_good_position_ = position;
  height_untrusted_time_ = 0.0;
}

void StateEstimator::Update(const LowState& frame, double dt) {
  const Eigen::Quaterniond orientation(frame.imu.quaternion[0], frame.imu.quaternion[1], frame.imu.quaternion[2],
                                       frame.imu.quaternion[3]);
  const Eigen::Matrix3d r = orientation.normalized().toRotationMatrix();
  const Eigen::Vector3d gyro(frame.imu.gyroscope[0], frame.imu.gyroscope[1], frame.imu.gyroscope[2]);
  const Eigen::Vector3d specific_force(frame.imu.accelerometer[0], frame.imu.accelerometer[1],
                                       frame.imu.accelerometer[2]);

  // Predict with the accelerometer: a = R f + g.
  if (dt > 0.0) {
    const Eigen::Vector3d a = r * specific_force - Eigen::Vector3d(0.0, 0.0, kGravity);
    x_.head<3>() += x_.tail<3>() * dt + 0.5 * a * dt * dt;
    x_.tail<3>() += a * dt;
    Matrix6d f = Matrix6d::Identity();
    f.topRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * dt;
    Eigen::Matrix<double, 6, 3> g;
    g << Eigen::Matrix3d::Identity() * (0.5 * dt * dt), Eigen::Matrix3d::Identity() * dt;
    const double s = config_.accelerometer_noise;
    p_ = f * p_ * f.transpose() + g * g.transpose() * (s * s);
  }

  // Measure with the stance feet: a still foot pins the base's velocity and height. Each foot is
  // its own measurement, gated: a foot whose squared Mahalanobis distance from what the filter
  // expects is beyond the gate is slipping (or not really in stance), and its velocity is left
  // out. A sliding foot is still on the floor, so its height is used under a gate of its own:
  // without it, a gait whose every foot slides (a turn in place) left the height to the
  // accelerometer alone, and it drifted by 0.1 m.
  bool in_stance = false, height_trusted = false;
  double nearest_rejected_height = HUGE_VAL;  // squared innovation
  for (int leg = 0; leg < a1::kNumLegs; ++leg) {
    const double force = frame.foot_force[leg];
    state_.foot_force[leg] = force;
    state_.foot_contact[leg] = force > config_.contact_threshold;
    if (!state_.foot_contact[leg]) continue;
    in_stance = true;
    double q[3], qd[3];
    for (int i = 0; i < 3; ++i) {
      q[i] = frame.motors[leg * 3 + i].q;
      qd[i] = frame.motors[leg * 3 + i].dq;
    }
    Eigen::Matrix3d jacobian;
    const Eigen::Vector3d foot = kinematics_.FootPosition(leg, q, &jacobian);
    const Eigen::Vector3d foot_velocity = jacobian * Eigen::Map<const Eigen::Vector3d>(qd) + gyro.cross(foot);
    Eigen::Vector4d z;
    z << -(r * foot_velocity), a1::kFootRadius - (r * foot).z();
    Eigen::Matrix<double, 4, 6> h = Eigen::Matrix<double, 4, 6>::Zero();
    h.block<3, 3>(0, 3) = Eigen::Matrix3d::Identity();
    h(3, 2) = 1.0;
    Eigen::Vector4d noise;
    noise << Eigen::Vector3d::Constant(config_.leg_velocity_noise * config_.leg_velocity_noise),
        config_.leg_height_noise * config_.leg_height_noise;
    const Eigen::Matrix4d s = h * p_ * h.transpose() + Eigen::Matrix4d(noise.asDiagonal());
    const Eigen::Vector4d innovation = z - h * x_;
    const Eigen::Matrix4d s_inverse = s.ldlt().solve(Eigen::Matrix4d::Identity());
    if (innovation.dot(s_inverse * innovation) <= config_.slip_gate) {
      const Eigen::Matrix<double, 6, 4> k = p_ * h.transpose() * s_inverse;
      x_ += k * innovation;
      p_ = (Matrix6d::Identity() - k * h) * p_;
      height_trusted = true;
      continue;
    }
    const double height_innovation = innovation(3), height_variance = s(3, 3);
    if (!(height_innovation * height_innovation <= config_.slip_gate * height_variance)) {
      nearest_rejected_height = std::min(nearest_rejected_height, height_innovation * height_innovation);
      continue;
    }
    const Vector6d k = p_.col(2) / height_variance;
    x_ += k * height_innovation;
    p_ -= k * p_.row(2);
    height_trusted = true;
  }
  // Time in stance since a foot was last trusted for height; flight neither counts nor clears it.
  if (height_trusted) {
    height_untrusted_time_ = 0.0;
  } else if (in_stance) {
    height_untrusted_time_ += dt;
  }
  if (height_untrusted_time_ > config_.height_reacquire_time && std::isfinite(nearest_rejected_height)) {
    // Adding to the diagonal keeps the covariance positive definite.
    p_(2, 2) += nearest_rejected_height;
    height_untrusted_time_ = 0.0;
  }

  if (!x_.allFinite() || !p_.allFinite()) Reset(last_good_position_);  // never stay poisoned
  last_good_position_ = x_.head<3>();

  state_.time = frame.tick * 1e-6;
  state_.base_position = x_.head<3>();
  state_.base_orientation = orientation.normalized();
  state_.base_linear_velocity = r.transpose() * x_.tail<3>();
  state_.base_angular_velocity = gyro;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    state_.joint_position[j] = frame.motors[j].q;
    state_.joint_velocity[j] = frame.motors[j].dq;
    state_.joint_torque[j] = frame.motors[j].tau_estimate;
  }
}

}  // namespace flsd::hw
