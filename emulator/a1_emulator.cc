#include "emulator/a1_emulator.h"

#include <algorithm>
#include <chrono>
#include <deque>
#include <cmath>
#include <random>

#include "core/rng.h"

namespace flsd::hw {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kGravity = 9.81;

}  // namespace

A1Emulator::A1Emulator(const EmulatorConfig& config)
    : config_(config), socket_(config.host, config.port), sim_(config.sim) {
  state_ = frozen_state_ = sim_.Read();
}

void A1Emulator::Start() {
  running_ = true;
  command_thread_ = std::thread([this] { ServeCommands(); });
  physics_thread_ = std::thread([this] { RunPhysics(); });
}

void A1Emulator::Stop() {
  if (!running_.exchange(false)) return;
  command_thread_.join();
  physics_thread_.join();
}

void A1Emulator::SetFaults(const EmulatorFaults& faults) {
  std::lock_guard<std::mutex> lock(mutex_);
  if ((faults.frozen_imu && !faults_.frozen_imu) || (faults.frozen_joints && !faults_.frozen_joints)) {
    frozen_state_ = state_;
  }
  faults_ = faults;
}

EmulatorStats A1Emulator::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

LowCommand A1Emulator::last_command() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return command_;
}

RobotState A1Emulator::TrueState() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return state_;
}

// The motors: each runs tau = tau_ff + Kp (q* - q) + Kd (dq* - dq) in servo mode, nothing in
// damping mode, as the A1's motor drivers do; the simulator clips it to 33.5 N m and to the
// motors' torque-speed line (MotorTorque).
void A1Emulator::RunPhysics() {
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a1::kPhysicsDt));
  auto next = Clock::now();
  while (running_) {
    JointCommand motors;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (int j = 0; have_command_ && j < a1::kNumJoints; ++j) {
        const MotorCommand& m = command_.motors[j];
        if (m.mode != kModeServo || j == faults_.dead_motor) continue;
        // The stop sentinels switch a loop off, as on the robot.
        const bool position_loop = std::abs(m.q) < kPositionStop / 2;
        const bool velocity_loop = std::abs(m.dq) < kVelocityStop / 2;
        motors.position[j] = position_loop ? m.q : 0.0;
        motors.kp[j] = position_loop ? m.kp : 0.0;
        motors.velocity[j] = velocity_loop ? m.dq : 0.0;
        motors.kd[j] = m.kd;
        motors.torque[j] = m.tau;
      }
    }
    sim_.env().StepCommand(motors, 1);
    const RobotState s = sim_.env().state();
    const Eigen::Vector3d world_velocity = s.base_orientation * s.base_linear_velocity;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const Eigen::Vector3d acceleration = (world_velocity - previous_world_velocity_) / a1::kPhysicsDt;
      specific_force_ = s.base_orientation.conjugate() * (acceleration + Eigen::Vector3d(0.0, 0.0, kGravity));
      previous_world_velocity_ = world_velocity;
      state_ = s;
      ++stats_.physics_steps;
    }
    next += period;
    std::this_thread::sleep_until(next);
    if (Clock::now() - next > 10 * period) next = Clock::now();  // after a stall, no burst
  }
}

LowState MakeSensorFrame(const RobotState& s, const Eigen::Vector3d& specific_force, double gyro_noise,
                         double accelerometer_noise, Rng& rng) {
  LowState out;
  const Eigen::Quaterniond& q = s.base_orientation;
  out.imu.quaternion = {static_cast<float>(q.w()), static_cast<float>(q.x()), static_cast<float>(q.y()),
                        static_cast<float>(q.z())};
  const Eigen::Vector3d rpy(std::atan2(2.0 * (q.w() * q.x() + q.y() * q.z()), 1.0 - 2.0 * (q.x() * q.x() + q.y() * q.y())),
                            std::asin(std::clamp(2.0 * (q.w() * q.y() - q.z() * q.x()), -1.0, 1.0)),
                            YawOf(q));
  // A real IMU is noisy: its readings never repeat exactly, which is how a frozen one shows.
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int k = 0; k < 3; ++k) {
    out.imu.gyroscope[k] = static_cast<float>(s.base_angular_velocity[k] + gyro_noise * noise(rng));
    out.imu.accelerometer[k] = static_cast<float>(specific_force[k] + accelerometer_noise * noise(rng));
    out.imu.rpy[k] = static_cast<float>(rpy[k]);
  }
  out.imu.temperature = 35;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    MotorState& m = out.motors[j];
    m.mode = kModeServo;
    m.q = m.q_raw = static_cast<float>(s.joint_position[j]);
    m.dq = m.dq_raw = static_cast<float>(s.joint_velocity[j]);
    m.tau_estimate = static_cast<float>(s.joint_torque[j]);
    m.temperature = 40;
  }
  for (int leg = 0; leg < a1::kNumLegs; ++leg) {
    out.foot_force[leg] = static_cast<int16_t>(std::lround(std::min(s.foot_force[leg], 32767.0)));
  }
  out.tick = static_cast<uint32_t>(std::llround(s.time * 1e6));
  return out;
}

LowState A1Emulator::MakeState(Rng& rng) {
  LowState out = MakeSensorFrame(state_, specific_force_, config_.gyro_noise, config_.accelerometer_noise, rng);
  if (faults_.frozen_imu || faults_.frozen_joints) {
    // A hung sensor: the same readings, noise and all, frame after frame, while the rest runs on.
    Rng frozen_rng(StreamSeed(config_.seed, 1));
    const LowState frozen = MakeSensorFrame(frozen_state_, Eigen::Vector3d(0.0, 0.0, kGravity), config_.gyro_noise,
                                            config_.accelerometer_noise, frozen_rng);
    if (faults_.frozen_imu) out.imu = frozen.imu;
    for (int j = 0; faults_.frozen_joints && j < a1::kNumJoints; ++j) out.motors[j] = frozen.motors[j];
  }
  if (faults_.dead_motor >= 0) out.motors[faults_.dead_motor].mode = kModeDamping;
  return out;
}

void A1Emulator::ServeCommands() {
  Rng rng(StreamSeed(config_.seed, 0));
  struct Pending {  // a state frame held back by the late-frame fault
    Clock::time_point due;
    std::array<uint8_t, kLowStateSize> frame;
    sockaddr_in to;
  };
  std::deque<Pending> pending;
  uint8_t in[2048];
  while (running_) {
    // Send what has come due, then wait for a command no longer than until the next is due.
    while (!pending.empty() && pending.front().due <= Clock::now()) {
      if (socket_.SendTo(pending.front().frame.data(), kLowStateSize, pending.front().to)) {
        std::lock_guard<std::mutex> lock(mutex_);
        ++stats_.states_sent;
      }
      pending.pop_front();
    }
    auto wait = std::chrono::microseconds(10000);
    if (!pending.empty()) {
      wait = std::min(wait, std::chrono::duration_cast<std::chrono::microseconds>(pending.front().due - Clock::now()));
    }
    sockaddr_in from{};
    const int n = socket_.Receive(in, sizeof in, std::max(wait, std::chrono::microseconds(0)), &from);
    if (n < 0) continue;
    Pending reply{Clock::now(), {}, from};
    EmulatorFaults faults;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      LowCommand command;
      if (DecodeLowCommand(in, static_cast<std::size_t>(n), command) != FrameError::kNone) {
        ++stats_.bad_commands;
        continue;
      }
      ++stats_.commands;
      command_ = command;
      have_command_ = true;
      faults = faults_;
      EncodeLowState(MakeState(rng), reply.frame.data());
    }
    if (faults.silent || Uniform(rng, 0.0, 1.0) < faults.drop_fraction) continue;
    if (Uniform(rng, 0.0, 1.0) < faults.corrupt_fraction) reply.frame[100] ^= 0x5A;
    // Late frames are delayed, each by the same time; the robot keeps taking commands meanwhile.
    reply.due += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(faults.late_ms));
    pending.push_back(reply);
  }
}

}  // namespace flsd::hw
