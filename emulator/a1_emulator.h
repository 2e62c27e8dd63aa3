#pragma once
// Plays the A1's side of the low-level UDP protocol on loopback, backed by the MuJoCo A1: it
// answers every command frame with a state frame, and its motors run the commanded PD law at
// every 5 ms physics step, in real time. Faults can be injected while it runs, so that the whole
// hardware path (server -> driver -> UDP -> robot -> UDP -> estimator -> policy) can be tested.

#include <atomic>
#include <mutex>
#include <string>
#include <thread>

#include "core/rng.h"
#include "hw/a1_protocol.h"
#include "hw/udp_socket.h"
#include "sim/sim_backend.h"

namespace flsd::hw {

struct EmulatorFaults {
  double drop_fraction = 0.0;     // of state frames never sent
  double corrupt_fraction = 0.0;  // of state frames sent with a broken CRC
  double late_ms = 0.0;           // every state frame is sent this long after its command came
  bool frozen_imu = false;        // IMU readings stop changing (a hung IMU)
  bool frozen_joints = false;     // joint encoder readings stop changing (a hung motor bus)
  int dead_motor = -1;            // this joint's motor produces no torque and reports mode 0
  bool silent = false;            // no state frames at all (a pulled cable)
};

struct EmulatorConfig {
  std::string host = "127.0.0.1";
  int port = 8007;  // the A1's low-level port; 0 picks a free one (tests)
  SimBackendConfig sim;
  int seed = 1;  // for sensor noise, and for dropping and corrupting frames
  double gyro_noise = 0.005;          // rad/s, standard deviation per frame
  double accelerometer_noise = 0.05;  // m/s^2
};

struct EmulatorStats {
  uint64_t commands = 0;      // valid command frames received
  uint64_t bad_commands = 0;  // rejected (length, level, CRC)
  uint64_t states_sent = 0;
  uint64_t physics_steps = 0;
};

// What the A1's sensors would report for the simulated state `s`: the IMU (attitude, gyro with
// noise, specific force with noise), the joint encoders, and the foot force sensors (in newtons).
LowState MakeSensorFrame(const RobotState& s, const Eigen::Vector3d& specific_force, double gyro_noise,
                         double accelerometer_noise, Rng& rng);

class A1Emulator {
 public:
  explicit A1Emulator(const EmulatorConfig& config);
  ~A1Emulator() { Stop(); }

  void Start();
  void Stop();

  void SetFaults(const EmulatorFaults& faults);
  int port() const { return socket_.port(); }
  EmulatorStats stats() const;
  LowCommand last_command() const;
  // The simulated robot's true state (for judging the estimator against ground truth).
  RobotState TrueState() const;

 private:
  void ServeCommands();
  void RunPhysics();
  LowState MakeState(Rng& rng);

  EmulatorConfig config_;
  UdpSocket socket_;
  SimBackend sim_;

  mutable std::mutex mutex_;  // guards everything below
  LowCommand command_;
  bool have_command_ = false;
  EmulatorFaults faults_;
  EmulatorStats stats_;
  RobotState state_, frozen_state_;
  Eigen::Vector3d previous_world_velocity_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d specific_force_{0.0, 0.0, 9.81};  // body frame

  std::atomic<bool> running_{false};
  std::thread command_thread_, physics_thread_;
};

}  // namespace flsd::hw
