#pragma once
// The Unitree A1's low-level UDP protocol (unitree_legged_sdk v3.2/v3.3), written from the wire
// format, with no vendor code. The SDK's C++ structs are NOT what travels: on the wire a command
// is 610 bytes (tau, Kp, Kd as int16 fixed point) and a state 771 bytes (ddq, tauEst, ddq_raw as
// int16), packed, little-endian, ending in a word-wise CRC-32. Offsets and scales are those of
// the SDK's compiled library, each pinned by tests/hw/a1_protocol_test.cc.

#include <array>
#include <cstddef>
#include <cstdint>

namespace flsd::hw {

inline constexpr std::size_t kLowCommandSize = 610;
inline constexpr std::size_t kLowStateSize = 771;
inline constexpr int kMotorSlots = 20;  // the frame has 20; the A1 uses 0..11 in robot/a1.h order
inline constexpr uint8_t kLowLevel = 0xFF;
inline constexpr uint8_t kModeServo = 0x0A;    // FOC servo: tau = tau_ff + Kp (q* - q) + Kd (dq* - dq)
inline constexpr uint8_t kModeDamping = 0x00;  // motor off / damping
inline constexpr float kPositionStop = 2.146e9f;  // q* meaning "no position loop"
inline constexpr float kVelocityStop = 16000.0f;  // dq* meaning "no velocity loop"

// The A1's CRC: polynomial 0x04C11DB7, initial value 0xFFFFFFFF, no reflection, no final XOR,
// over `words` 32-bit little-endian words each fed most significant bit first.
uint32_t Crc32Words(const uint8_t* data, std::size_t words);

struct MotorCommand {
  uint8_t mode = kModeDamping;
  float q = 0.0f, dq = 0.0f, tau = 0.0f, kp = 0.0f, kd = 0.0f;
};

struct LowCommand {
  uint8_t level_flag = kLowLevel;
  uint16_t comm_version = 0;
  uint16_t robot_id = 0;
  uint32_t serial_number = 0;
  uint8_t bandwidth = 0;
  std::array<MotorCommand, kMotorSlots> motors{};
  std::array<uint8_t, 40> wireless_remote{};
};

struct MotorState {
  uint8_t mode = 0;
  float q = 0.0f, dq = 0.0f, ddq = 0.0f, tau_estimate = 0.0f, q_raw = 0.0f, dq_raw = 0.0f, ddq_raw = 0.0f;
  int8_t temperature = 0;  // deg C
};

struct Imu {
  std::array<float, 4> quaternion{1.0f, 0.0f, 0.0f, 0.0f};  // w, x, y, z: body to world
  std::array<float, 3> gyroscope{};      // rad/s, body frame
  std::array<float, 3> accelerometer{};  // m/s^2, body frame (specific force: +g when at rest)
  std::array<float, 3> rpy{};            // rad
  int8_t temperature = 0;
};

struct LowState {
  uint8_t level_flag = kLowLevel;
  uint16_t comm_version = 0;
  uint16_t robot_id = 0;
  uint32_t serial_number = 0;
  uint8_t bandwidth = 0;
  Imu imu;
  std::array<MotorState, kMotorSlots> motors{};
  std::array<int16_t, 4> foot_force{};           // raw sensor units, FR FL RR RL
  std::array<int16_t, 4> foot_force_estimate{};
  uint32_t tick = 0;  // us, the robot's clock
  std::array<uint8_t, 40> wireless_remote{};
};

enum class FrameError { kNone, kLength, kLevel, kCrc };
const char* ToString(FrameError error);

// Writes the 610-byte wire frame, CRC included. tau, Kp and Kd saturate at what int16 holds
// (|tau| < 128 N m, Kp < 1024, Kd < 2048).
void EncodeLowCommand(const LowCommand& command, uint8_t* frame);
FrameError DecodeLowCommand(const uint8_t* frame, std::size_t size, LowCommand& command);

void EncodeLowState(const LowState& state, uint8_t* frame);
FrameError DecodeLowState(const uint8_t* frame, std::size_t size, LowState& state);

}  // namespace flsd::hw
