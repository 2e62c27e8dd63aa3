#pragma once
// The real A1 backend's settings (configs/server.yaml's `hw:` section), apart from the driver, so
// that the server's config can name them without including sockets or the driver.

#include <string>

#include "core/config.h"

namespace flsd::hw {

struct EstimatorConfig {
  double contact_threshold = 20.0;  // foot force above which a foot is in stance (sensor units)
  double accelerometer_noise = 1.0;  // m/s^2, drives the process noise
  double leg_velocity_noise = 0.05;  // m/s, per stance foot
  double leg_height_noise = 0.01;    // m, per stance foot
  // A foot whose squared Mahalanobis distance (4 degrees of freedom: velocity and height) is above
  // this slips. 9 keeps 94 % of feet that do not slip (chi-square); tuned on the shipped skills.
  double slip_gate = 9.0;
  // s with a foot in stance but none trusted for height, after which the height's variance widens
  // to take the nearest foot again: gated, a height that drifted past the gate in a hopping gait's
  // flight never came back (0.07 m RMS on a 1.9 rad/s turn in place).
  double height_reacquire_time = 0.1;
  template <class V>
  void Visit(V& v) {
    v("contact_threshold", contact_threshold, Bounds<double>{0.0, 10000.0});
    v("accelerometer_noise", accelerometer_noise, Bounds<double>{1e-4, 100.0});
    v("leg_velocity_noise", leg_velocity_noise, Bounds<double>{1e-4, 10.0});
    v("leg_height_noise", leg_height_noise, Bounds<double>{1e-5, 1.0});
    v("slip_gate", slip_gate, Bounds<double>{0.5, 10000.0});
    v("height_reacquire_time", height_reacquire_time, Bounds<double>{0.0, 10.0});
  }
};

struct HwConfig {
  std::string local_host = "0.0.0.0";
  int local_port = 8080;                     // the SDK's local port
  std::string robot_host = "192.168.123.10";  // the A1's motion MCU
  int robot_port = 8007;
  double rate_hz = 500.0;
  double stale_after = 0.1;   // s without a valid state frame: damp
  double frozen_after = 0.1;  // s of bit-identical IMU readings, or joint readings while turning: damp
  double motor_mode_after = 0.05;  // s of a motor not in servo mode while commanded: damp
  double command_timeout = 0.1;    // s without a command from the control loop: the driver damps
  double damping_kd = 1.0;         // N m s / rad of the driver's own damping
  double max_motor_temperature = 70.0;  // deg C, checked before torque is enabled
  double max_preflight_tilt = 0.5;      // rad
  double preflight_seconds = 1.0;       // of clean frames required before torque
  int driver_priority = 90;  // SCHED_FIFO priority of the 500 Hz driver thread; 0: normal scheduler
  std::string urdf = "robot/a1/a1.urdf";
  EstimatorConfig estimator;
  template <class V>
  void Visit(V& v) {
    v("local_host", local_host);
    v("local_port", local_port, Bounds<int>{0, 65535});
    v("robot_host", robot_host);
    v("robot_port", robot_port, Bounds<int>{1, 65535});
    v("rate_hz", rate_hz, Bounds<double>{50.0, 2000.0});
    v("stale_after", stale_after, Bounds<double>{0.005, 5.0});
    v("frozen_after", frozen_after, Bounds<double>{0.005, 5.0});
    v("motor_mode_after", motor_mode_after, Bounds<double>{0.002, 5.0});
    v("command_timeout", command_timeout, Bounds<double>{0.02, 5.0});
    v("damping_kd", damping_kd, Bounds<double>{0.0, 10.0});
    v("max_motor_temperature", max_motor_temperature, Bounds<double>{20.0, 120.0});
    v("max_preflight_tilt", max_preflight_tilt, Bounds<double>{0.05, 3.2});
    v("preflight_seconds", preflight_seconds, Bounds<double>{0.05, 60.0});
    v("driver_priority", driver_priority, Bounds<int>{0, 99});
    v("urdf", urdf);
    v("estimator", estimator);
  }
};

}  // namespace flsd::hw
