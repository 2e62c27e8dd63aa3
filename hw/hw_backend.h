#pragma once
// The real A1 as the server's backend, over its low-level UDP interface. A driver thread runs at
// 500 Hz: it sends the newest joint command (the motor drivers run the PD law at Kp, Kd), reads
// the newest valid state frame, and folds it into the state estimator. The 50 Hz control loop
// hands commands in and takes states out through lock-free triple buffers.

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "core/config.h"
#include "core/latency_histogram.h"
#include "core/triple_buffer.h"
#include "hw/a1_protocol.h"
#include "hw/state_estimator.h"
#include "hw/udp_socket.h"
#include "robot/backend.h"

namespace flsd::hw {

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

struct DriverStats {
  uint64_t sent = 0, received = 0, bad_length = 0, bad_level = 0, bad_crc = 0;
  uint64_t bad_values = 0;  // CRC fine, but non-finite numbers or an attitude that is no rotation
  uint64_t cycles = 0, late_cycles = 0;  // late: started more than half a period after its time
};

class HwBackend final : public Backend {
 public:
  explicit HwBackend(const HwConfig& config);
  ~HwBackend() override;

  const char* name() const override { return "hw"; }
  void Send(const JointCommand& command) override;
  RobotState Read() override;
  std::string Fault() const override;

  // Checks, before any torque: state frames arrive and pass their CRC, joints are inside their
  // ranges, the IMU is upright, motor temperatures are sane. Returns one message per failure.
  std::vector<std::string> Preflight();

  DriverStats stats() const;
  // How late each send was against its 2 ms schedule, and how long each state frame took to
  // come back after the command that asked for it.
  const LatencyHistogram& send_lateness() const { return send_lateness_; }
  const LatencyHistogram& round_trip() const { return round_trip_; }
  bool realtime() const { return realtime_; }

 private:
  enum class FaultCode : int { kNone, kStale, kFrozenImu, kFrozenJoints, kMotorMode, kNoCommand };
  void Run();
  LowCommand ToLowCommand(const JointCommand& command) const;

  HwConfig config_;
  UdpSocket socket_;
  StateEstimator estimator_;
  TripleBuffer<JointCommand> commands_;
  TripleBuffer<RobotState> states_;
  TripleBuffer<LowState> frames_;  // the raw newest frame, for the pre-flight check
  std::atomic<bool> have_command_{false};
  std::atomic<int64_t> last_command_ns_{0};  // steady clock
  std::atomic<bool> running_{true};
  std::atomic<int> fault_{0};
  std::atomic<int> fault_joint_{-1};
  std::atomic<double> since_valid_{0.0};
  std::atomic<uint64_t> sent_{0}, received_{0}, bad_length_{0}, bad_level_{0}, bad_crc_{0}, bad_values_{0};
  std::atomic<uint64_t> cycles_{0}, late_{0};
  LatencyHistogram send_lateness_, round_trip_;
  bool realtime_ = false;
  std::thread thread_;
};

}  // namespace flsd::hw
