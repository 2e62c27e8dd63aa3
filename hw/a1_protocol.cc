#include "hw/a1_protocol.h"

#include <cmath>
#include <cstring>
#include <type_traits>

namespace flsd::hw {
namespace {

// Little-endian field access, independent of the host's byte order.
template <class T>
void Put(uint8_t* frame, std::size_t offset, T value) {
  static_assert(std::is_integral_v<T>);
  using U = std::make_unsigned_t<T>;
  const U u = static_cast<U>(value);
  for (std::size_t i = 0; i < sizeof(T); ++i) frame[offset + i] = static_cast<uint8_t>(u >> (8 * i));
}
void PutFloat(uint8_t* frame, std::size_t offset, float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  Put(frame, offset, bits);
}
template <class T>
T Get(const uint8_t* frame, std::size_t offset) {
  using U = std::make_unsigned_t<T>;
  U u = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) u |= static_cast<U>(static_cast<U>(frame[offset + i]) << (8 * i));
  return static_cast<T>(u);
}
float GetFloat(const uint8_t* frame, std::size_t offset) {
  const uint32_t bits = Get<uint32_t>(frame, offset);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// x * scale as int16, rounded toward zero (as the SDK's float-to-int cast), saturated.
int16_t FixedPoint(float x, float scale) {
  const float v = std::trunc(x * scale);
  if (!(v > -32768.0f)) return v != v ? 0 : -32768;  // NaN encodes as 0
  return v >= 32767.0f ? 32767 : static_cast<int16_t>(v);
}

// The 10-byte header shared by both frames.
template <class M>
void PutHeader(const M& m, uint8_t* frame) {
  frame[0] = m.level_flag;
  Put(frame, 1, m.comm_version);
  Put(frame, 3, m.robot_id);
  Put(frame, 5, m.serial_number);
  frame[9] = m.bandwidth;
}
template <class M>
void GetHeader(const uint8_t* frame, M& m) {
  m.level_flag = frame[0];
  m.comm_version = Get<uint16_t>(frame, 1);
  m.robot_id = Get<uint16_t>(frame, 3);
  m.serial_number = Get<uint32_t>(frame, 5);
  m.bandwidth = frame[9];
}

FrameError Check(const uint8_t* frame, std::size_t size, std::size_t expected) {
  if (size != expected) return FrameError::kLength;
  if (frame[0] != kLowLevel) return FrameError::kLevel;
  const std::size_t crc_offset = expected - 4;
  if (Crc32Words(frame, expected / 4 - 1) != Get<uint32_t>(frame, crc_offset)) return FrameError::kCrc;
  return FrameError::kNone;
}

void PutCrc(uint8_t* frame, std::size_t size) { Put(frame, size - 4, Crc32Words(frame, size / 4 - 1)); }

constexpr std::size_t kCommandMotors = 10, kCommandMotorStride = 27, kCommandRemote = 562;
constexpr std::size_t kStateImu = 10, kStateMotors = 63, kStateMotorStride = 32, kStateFootForce = 703,
                      kStateFootForceEstimate = 711, kStateTick = 719, kStateRemote = 723;

}  // namespace

uint32_t Crc32Words(const uint8_t* data, std::size_t words) {
  uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t w = 0; w < words; ++w) {
    const uint32_t word = Get<uint32_t>(data, 4 * w);
    for (int bit = 31; bit >= 0; --bit) {
      const bool top = (crc ^ (word << (31 - bit))) & 0x80000000u;
      crc = top ? (crc << 1) ^ 0x04C11DB7u : crc << 1;
    }
  }
  return crc;
}

const char* ToString(FrameError error) {
  switch (error) {
    case FrameError::kNone: return "ok";
    case FrameError::kLength: return "wrong length";
    case FrameError::kLevel: return "not a low-level frame";
    case FrameError::kCrc: return "CRC mismatch";
  }
  return "unknown";
}

void EncodeLowCommand(const LowCommand& c, uint8_t* frame) {
  std::memset(frame, 0, kLowCommandSize);
  PutHeader(c, frame);
  for (int i = 0; i < kMotorSlots; ++i) {
    const MotorCommand& m = c.motors[i];
    const std::size_t o = kCommandMotors + kCommandMotorStride * i;
    frame[o] = m.mode;
    PutFloat(frame, o + 1, m.q);
    PutFloat(frame, o + 5, m.dq);
    Put(frame, o + 9, FixedPoint(m.tau, 256.0f));
    Put(frame, o + 11, FixedPoint(m.kp, 32.0f));
    Put(frame, o + 13, FixedPoint(m.kd, 16.0f));
  }
  std::memcpy(frame + kCommandRemote, c.wireless_remote.data(), c.wireless_remote.size());
  PutCrc(frame, kLowCommandSize);
}

FrameError DecodeLowCommand(const uint8_t* frame, std::size_t size, LowCommand& c) {
  const FrameError error = Check(frame, size, kLowCommandSize);
  if (error != FrameError::kNone) return error;
  GetHeader(frame, c);
  for (int i = 0; i < kMotorSlots; ++i) {
    MotorCommand& m = c.motors[i];
    const std::size_t o = kCommandMotors + kCommandMotorStride * i;
    m.mode = frame[o];
    m.q = GetFloat(frame, o + 1);
    m.dq = GetFloat(frame, o + 5);
    m.tau = Get<int16_t>(frame, o + 9) / 256.0f;
    m.kp = Get<int16_t>(frame, o + 11) / 32.0f;
    m.kd = Get<int16_t>(frame, o + 13) / 16.0f;
  }
  std::memcpy(c.wireless_remote.data(), frame + kCommandRemote, c.wireless_remote.size());
  return FrameError::kNone;
}

void EncodeLowState(const LowState& s, uint8_t* frame) {
  std::memset(frame, 0, kLowStateSize);
  PutHeader(s, frame);
  for (int k = 0; k < 4; ++k) PutFloat(frame, kStateImu + 4 * k, s.imu.quaternion[k]);
  for (int k = 0; k < 3; ++k) {
    PutFloat(frame, kStateImu + 16 + 4 * k, s.imu.gyroscope[k]);
    PutFloat(frame, kStateImu + 28 + 4 * k, s.imu.accelerometer[k]);
    PutFloat(frame, kStateImu + 40 + 4 * k, s.imu.rpy[k]);
  }
  frame[kStateImu + 52] = static_cast<uint8_t>(s.imu.temperature);
  for (int i = 0; i < kMotorSlots; ++i) {
    const MotorState& m = s.motors[i];
    const std::size_t o = kStateMotors + kStateMotorStride * i;
    frame[o] = m.mode;
    PutFloat(frame, o + 1, m.q);
    PutFloat(frame, o + 5, m.dq);
    Put(frame, o + 9, FixedPoint(m.ddq, 1.0f));
    Put(frame, o + 11, FixedPoint(m.tau_estimate, 256.0f));
    PutFloat(frame, o + 13, m.q_raw);
    PutFloat(frame, o + 17, m.dq_raw);
    Put(frame, o + 21, FixedPoint(m.ddq_raw, 1.0f));
    frame[o + 23] = static_cast<uint8_t>(m.temperature);
  }
  for (int k = 0; k < 4; ++k) {
    Put(frame, kStateFootForce + 2 * k, s.foot_force[k]);
    Put(frame, kStateFootForceEstimate + 2 * k, s.foot_force_estimate[k]);
  }
  Put(frame, kStateTick, s.tick);
  std::memcpy(frame + kStateRemote, s.wireless_remote.data(), s.wireless_remote.size());
  PutCrc(frame, kLowStateSize);
}

FrameError DecodeLowState(const uint8_t* frame, std::size_t size, LowState& s) {
  const FrameError error = Check(frame, size, kLowStateSize);
  if (error != FrameError::kNone) return error;
  GetHeader(frame, s);
  for (int k = 0; k < 4; ++k) s.imu.quaternion[k] = GetFloat(frame, kStateImu + 4 * k);
  for (int k = 0; k < 3; ++k) {
    s.imu.gyroscope[k] = GetFloat(frame, kStateImu + 16 + 4 * k);
    s.imu.accelerometer[k] = GetFloat(frame, kStateImu + 28 + 4 * k);
    s.imu.rpy[k] = GetFloat(frame, kStateImu + 40 + 4 * k);
  }
  s.imu.temperature = static_cast<int8_t>(frame[kStateImu + 52]);
  for (int i = 0; i < kMotorSlots; ++i) {
    MotorState& m = s.motors[i];
    const std::size_t o = kStateMotors + kStateMotorStride * i;
    m.mode = frame[o];
    m.q = GetFloat(frame, o + 1);
    m.dq = GetFloat(frame, o + 5);
    m.ddq = Get<int16_t>(frame, o + 9);  // the SDK's scale for ddq is not known; unused here
    m.tau_estimate = Get<int16_t>(frame, o + 11) / 256.0f;
    m.q_raw = GetFloat(frame, o + 13);
    m.dq_raw = GetFloat(frame, o + 17);
    m.ddq_raw = Get<int16_t>(frame, o + 21);
    m.temperature = static_cast<int8_t>(frame[o + 23]);
  }
  for (int k = 0; k < 4; ++k) {
    s.foot_force[k] = Get<int16_t>(frame, kStateFootForce + 2 * k);
    s.foot_force_estimate[k] = Get<int16_t>(frame, kStateFootForceEstimate + 2 * k);
  }
  s.tick = Get<uint32_t>(frame, kStateTick);
  std::memcpy(s.wireless_remote.data(), frame + kStateRemote, s.wireless_remote.size());
  return FrameError::kNone;
}

}  // namespace flsd::hw
