#include "hw/hw_backend.h"

#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace flsd::hw {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// A frame whose CRC passed can still carry garbage: non-finite numbers, or an attitude that is
// not a rotation. Such a frame is counted and not used.
bool Plausible(const LowState& frame) {
  double norm = 0.0;
  for (float v : frame.imu.quaternion) norm += static_cast<double>(v) * v;
  if (!(std::abs(norm - 1.0) < 0.1)) return false;
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(frame.imu.gyroscope[k]) || !std::isfinite(frame.imu.accelerometer[k])) return false;
  }
  for (int j = 0; j < a1::kNumJoints; ++j) {
    if (!std::isfinite(frame.motors[j].q) || !std::isfinite(frame.motors[j].dq)) return false;
  }
  return true;
}

}  // namespace

HwBackend::HwBackend(const HwConfig& config)
    : config_(config),
      socket_(config.local_host, config.local_port),
      estimator_(LegKinematics::FromUrdf(config.urdf), config.estimator) {
  socket_.Connect(config.robot_host, config.robot_port);
  thread_ = std::thread([this] {
    prctl(PR_SET_TIMERSLACK, 1UL);
    Run();
  });
  if (config.driver_priority > 0) {
    sched_param param{};
    param.sched_priority = config.driver_priority;
    realtime_ = pthread_setschedparam(thread_.native_handle(), SCHED_FIFO, &param) == 0;
  }
}

HwBackend::~HwBackend() {
  running_ = false;
  thread_.join();
}

void HwBackend::Send(const JointCommand& command) {
  commands_.Write(command);
  last_command_ns_.store(Clock::now().time_since_epoch().count(), std::memory_order_relaxed);
  have_command_.store(true, std::memory_order_release);
}

RobotState HwBackend::Read() {
  RobotState s;
  states_.Read(s);
  return s;
}

std::string HwBackend::Fault() const {
  char text[160];
  switch (static_cast<DriverFault>(fault_.load())) {
    case DriverFault::kNone: return {};
    case DriverFault::kStale:
      std::snprintf(text, sizeof text, "no valid state frame from the robot for %.0f ms", since_valid_.load() * 1e3);
      break;
    case DriverFault::kFrozenImu:
      std::snprintf(text, sizeof text, "IMU readings frozen (identical for over %.0f ms)", config_.frozen_after * 1e3);
      break;
    case DriverFault::kFrozenJoints:
      std::snprintf(text, sizeof text, "joint encoder readings frozen (identical for over %.0f ms while the body turns)",
                    config_.frozen_after * 1e3);
      break;
    case DriverFault::kNoCommand:
      std::snprintf(text, sizeof text, "no command from the control loop for over %.0f ms: the driver damps",
                    config_.command_timeout * 1e3);
      break;
    case DriverFault::kMotorMode:
      std::snprintf(text, sizeof text, "motor %s is not in servo mode", a1::kJointNames[std::max(0, fault_joint_.load())]);
      break;
  }
  return text;
}

DriverStats HwBackend::stats() const {
  return {sent_.load(),    received_.load(), bad_length_.load(), bad_level_.load(),
          bad_crc_.load(), bad_values_.load(), cycles_.load(),   late_.load()};
}

// Torque-free until the server commands: the SDK's initial command (servo mode, both loops off,
// no gains), which also makes the robot start sending state frames. A joint whose command is not
// finite is damped instead.
LowCommand HwBackend::ToLowCommand(const JointCommand& c) const {
  LowCommand out;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    MotorCommand& m = out.motors[j];
    m.mode = kModeServo;
    if (!std::isfinite(c.position[j]) || !std::isfinite(c.velocity[j]) || !std::isfinite(c.kp[j]) ||
        !std::isfinite(c.kd[j]) || !std::isfinite(c.torque[j])) {
      m.q = kPositionStop;
      m.dq = 0.0f;
      m.kd = static_cast<float>(config_.damping_kd);
      continue;
    }
    m.q = static_cast<float>(std::clamp(c.position[j], a1::JointMin(j), a1::JointMax(j)));
    m.dq = static_cast<float>(c.velocity[j]);
    m.kp = static_cast<float>(c.kp[j]);
    m.kd = static_cast<float>(c.kd[j]);
    m.tau = static_cast<float>(std::clamp(c.torque[j], -a1::kTorqueLimit, a1::kTorqueLimit));
    if (c.kp[j] == 0.0) m.q = kPositionStop;
    if (c.kd[j] == 0.0) m.dq = kVelocityStop;
  }
  return out;
}

void HwBackend::Run() {
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / config_.rate_hz));
  JointCommand command;  // all zero gains: torque-free
  uint8_t out[kLowCommandSize], in[2048];
  LowState frame;
  bool have_frame = false;
  uint32_t last_tick = 0;
  DriverMonitor monitor(config_, Clock::now());
  auto next = Clock::now();
  while (running_.load(std::memory_order_relaxed)) {
    // The command-loss watchdog: if the control loop stops handing commands over (hung, or
    // crashed), the driver damps on its own rather than hold the last targets forever.
    const bool commanded = have_command_.load(std::memory_order_acquire);
    if (commanded) commands_.Read(command);
    const bool command_lost =
        commanded && Seconds(Clock::now().time_since_epoch() -
                             Clock::duration(last_command_ns_.load(std::memory_order_relaxed))) > config_.command_timeout;
    EncodeLowCommand(ToLowCommand(command_lost ? JointCommand::Damp(config_.damping_kd) : command), out);
    const auto sent_at = Clock::now();
    if (sent_at - next > period / 2) late_.fetch_add(1, std::memory_order_relaxed);
    send_lateness_.Add(Seconds(sent_at - next));
    if (socket_.Send(out, sizeof out)) sent_.fetch_add(1, std::memory_order_relaxed);

    // Take every frame that arrives before the next send; keep the newest valid one.
    next += period;
    bool fresh = false;
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::microseconds>(next - Clock::now());
      const int n = socket_.Receive(in, sizeof in, std::max(left, std::chrono::microseconds(0)));
      if (n < 0) break;
      switch (DecodeLowState(in, static_cast<std::size_t>(n), frame)) {
        case FrameError::kNone:
          if (!Plausible(frame)) {
            bad_values_.fetch_add(1, std::memory_order_relaxed);
            break;
          }
          if (!fresh) round_trip_.Add(Seconds(Clock::now() - sent_at));
          fresh = true;
          break;
        case FrameError::kLength: bad_length_.fetch_add(1, std::memory_order_relaxed); break;
        case FrameError::kLevel: bad_level_.fetch_add(1, std::memory_order_relaxed); break;
        case FrameError::kCrc: bad_crc_.fetch_add(1, std::memory_order_relaxed); break;
      }
      if (fresh && left.count() <= 0) break;
    }
    const auto now = Clock::now();
    if (fresh) {
      received_.fetch_add(1, std::memory_order_relaxed);
      const double dt = have_frame ? static_cast<uint32_t>(frame.tick - last_tick) * 1e-6 : 0.0;
      estimator_.Update(frame, std::min(dt, 0.05));
      states_.Write(estimator_.state());
      frames_.Write(frame);
      monitor.OnFrame(frame, command, now);
      last_tick = frame.tick;
      have_frame = true;
    }
    since_valid_.store(monitor.SinceValid(now), std::memory_order_relaxed);
    fault_joint_.store(monitor.motor_mode_joint(), std::memory_order_relaxed);
    fault_.store(static_cast<int>(monitor.Check(command_lost, now)), std::memory_order_relaxed);
    cycles_.fetch_add(1, std::memory_order_relaxed);
    std::this_thread::sleep_until(next);
    if (Clock::now() - next > 10 * period) next = Clock::now();  // after a stall, no burst
  }
}

std::vector<std::string> HwBackend::Preflight() {
  std::vector<std::string> failures;
  const DriverStats before = stats();
  std::this_thread::sleep_for(std::chrono::duration<double>(config_.preflight_seconds));
  const DriverStats after = stats();
  const uint64_t received = after.received - before.received;
  const uint64_t sent = after.sent - before.sent;
  char text[320];
  const auto count = [](uint64_t n) { return static_cast<unsigned long long>(n); };
  const uint64_t bad_crc = after.bad_crc - before.bad_crc, bad_length = after.bad_length - before.bad_length;
  const uint64_t bad_level = after.bad_level - before.bad_level, bad_values = after.bad_values - before.bad_values;
  const uint64_t bad = bad_crc + bad_length + bad_level + bad_values;
  if (received == 0 && bad == 0) {
    std::snprintf(text, sizeof text,
                  "no state frame from the robot at %s:%d in %.1f s (%llu commands sent): is it on, in low-level mode, "
                  "and reachable on this network?",
                  config_.robot_host.c_str(), config_.robot_port, config_.preflight_seconds, count(sent));
    failures.push_back(text);
    return failures;
  }
  if (bad > 0) {
    // Frames that come but never pass are not a missing robot: the robot answers in a format this
    // build does not read (firmware, SDK version, or frame size).
    std::snprintf(text, sizeof text,
                  "%llu of %llu state frames were malformed (%llu bad CRC, %llu wrong length, %llu not low-level, %llu "
                  "implausible values)%s",
                  count(bad), count(bad + received), count(bad_crc), count(bad_length), count(bad_level),
                  count(bad_values),
                  received == 0 ? ": the robot answers, but not in the expected frame layout (a firmware or frame-size "
                                  "mismatch?)"
                                : "");
    failures.push_back(text);
    if (received == 0) return failures;
  }
  if (received < sent / 2) {
    std::snprintf(text, sizeof text, "only %llu state frames for %llu commands", static_cast<unsigned long long>(received),
                  static_cast<unsigned long long>(sent));
    failures.push_back(text);
  }
  LowState frame;
  frames_.Read(frame);
  for (int j = 0; j < a1::kNumJoints; ++j) {
    const double q = frame.motors[j].q;
    // The calves rest against their stops when the robot lies folded, and read up to ~0.06 rad past
    // them (measured on the emulator's lying robot): the margin of skilld's supervisor, 0.1 rad.
    if (!a1::WithinRange(j, q, 0.1)) {
      std::snprintf(text, sizeof text, "%s reads %.3f rad, outside its range [%.3f, %.3f]", a1::kJointNames[j], q,
                    a1::JointMin(j), a1::JointMax(j));
      failures.push_back(text);
    }
    if (frame.motors[j].mode != kModeServo) {  // commanded servo mode since the first frame
      std::snprintf(text, sizeof text, "%s motor reports mode 0x%02X, not servo mode (0x%02X): it is off or faulted",
                    a1::kJointNames[j], frame.motors[j].mode, kModeServo);
      failures.push_back(text);
    }
    if (frame.motors[j].temperature > config_.max_motor_temperature) {
      std::snprintf(text, sizeof text, "%s motor at %d C, above %.0f C", a1::kJointNames[j], frame.motors[j].temperature,
                    config_.max_motor_temperature);
      failures.push_back(text);
    }
  }
  const RobotState s = Read();
  const double tilt = std::acos(std::clamp(-s.ProjectedGravity().z(), -1.0, 1.0));
  if (tilt > config_.max_preflight_tilt) {
    std::snprintf(text, sizeof text, "the IMU reads a tilt of %.2f rad (more than %.2f): set the robot upright", tilt,
                  config_.max_preflight_tilt);
    failures.push_back(text);
  }
  if (const std::string fault = Fault(); !fault.empty()) failures.push_back(fault);
  return failures;
}

}  // namespace flsd::hw
