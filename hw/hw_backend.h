#pragma once
// The real A1 as the server's backend, over its low-level UDP interface. A driver thread runs at
// 500 Hz: it sends the newest joint command (the motor drivers run the PD law at Kp, Kd), reads
// the newest valid state frame, and folds it into the state estimator. The 50 Hz control loop
// hands commands in and takes states out through lock-free triple buffers.

#include <atomic>
#include <string>
#include <thread>
#include <vector>

#include "core/latency_histogram.h"
#include "core/triple_buffer.h"
#include "hw/a1_protocol.h"
#include "hw/driver_monitor.h"
#include "hw/hw_config.h"
#include "hw/state_estimator.h"
#include "hw/udp_socket.h"
#include "robot/backend.h"

namespace flsd::hw {


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
  std::atomic<int> fault_{0};  // a DriverFault
  std::atomic<int> fault_joint_{-1};
  std::atomic<double> since_valid_{0.0};
  std::atomic<uint64_t> sent_{0}, received_{0}, bad_length_{0}, bad_level_{0}, bad_crc_{0}, bad_values_{0};
  std::atomic<uint64_t> cycles_{0}, late_{0};
  LatencyHistogram send_lateness_, round_trip_;
  bool realtime_ = false;
  std::thread thread_;
};

}  // namespace flsd::hw
