// The A1 wire protocol against known answers: the CRC of fixed inputs (values from an
// independent CRC-32/MPEG-2 implementation that reproduces the standard check value 0x0376E6E7
// for "123456789"), byte offsets and fixed-point encodings written out by hand from the frame
// layout, round trips, and rejection of frames with a wrong length, level flag or CRC.

#include "hw/a1_protocol.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace flsd::hw {
namespace {

uint32_t Le32(const std::vector<uint8_t>& f, size_t o) {
  return f[o] | f[o + 1] << 8 | f[o + 2] << 16 | static_cast<uint32_t>(f[o + 3]) << 24;
}
int16_t Le16(const std::vector<uint8_t>& f, size_t o) { return static_cast<int16_t>(f[o] | f[o + 1] << 8); }
float LeFloat(const std::vector<uint8_t>& f, size_t o) {
  const uint32_t bits = Le32(f, o);
  float v;
  std::memcpy(&v, &bits, 4);
  return v;
}

TEST(Crc32Words, MatchesKnownAnswers) {
  const uint8_t digits[] = {'1', '2', '3', '4', '5', '6', '7', '8'};
  EXPECT_EQ(Crc32Words(digits, 2), 0xFEFC54F9u);
  const uint8_t flag[] = {0xFF, 0, 0, 0};
  EXPECT_EQ(Crc32Words(flag, 1), 0x76F39DCFu);
  const uint8_t zeros[8] = {};
  EXPECT_EQ(Crc32Words(zeros, 2), 0x6904BB59u);
  EXPECT_EQ(Crc32Words(zeros, 0), 0xFFFFFFFFu);
}

TEST(LowCommand, AnEmptyFrameHasTheLevelFlagAndItsCrcInTheLastWord) {
  std::vector<uint8_t> f(kLowCommandSize);
  EncodeLowCommand(LowCommand{}, f.data());
  EXPECT_EQ(f[0], 0xFF);
  for (size_t i = 1; i < 606; ++i) ASSERT_EQ(f[i], 0) << "byte " << i;
  EXPECT_EQ(Le32(f, 606), 0xA4819405u);  // CRC of 151 words: 0xFF then zeros
}

TEST(LowCommand, FieldsSitAtTheirWireOffsetsInFixedPoint) {
  LowCommand c;
  c.comm_version = 0x0102;
  c.robot_id = 0x0304;
  c.serial_number = 0x05060708;
  c.bandwidth = 9;
  MotorCommand& m = c.motors[3];
  m.mode = kModeServo;
  m.q = 0.8f;
  m.dq = -1.25f;
  m.tau = 1.5f;
  m.kp = 20.0f;
  m.kd = 0.5f;
  c.wireless_remote[39] = 0xAB;
  std::vector<uint8_t> f(kLowCommandSize);
  EncodeLowCommand(c, f.data());
  EXPECT_EQ(f[1], 0x02);
  EXPECT_EQ(f[2], 0x01);
  EXPECT_EQ(Le32(f, 5), 0x05060708u);
  EXPECT_EQ(f[9], 9);
  const size_t o = 10 + 27 * 3;  // 91
  EXPECT_EQ(f[o], 0x0A);
  EXPECT_EQ(LeFloat(f, o + 1), 0.8f);
  EXPECT_EQ(LeFloat(f, o + 5), -1.25f);
  EXPECT_EQ(Le16(f, o + 9), 384);  // 1.5 N m x 256
  EXPECT_EQ(Le16(f, o + 11), 640);  // Kp 20 x 32
  EXPECT_EQ(Le16(f, o + 13), 8);    // Kd 0.5 x 16
  EXPECT_EQ(f[601], 0xAB);          // wireless remote: 562..601
  EXPECT_EQ(Le32(f, 606), Crc32Words(f.data(), 151));
}

TEST(LowCommand, FixedPointRoundsTowardZeroAndSaturates) {
  LowCommand c;
  c.motors[0].tau = -0.0039f;  // -0.998 units: 0
  c.motors[1].tau = -1.00390625f;  // exactly -257 units
  c.motors[2].tau = 200.0f;
  c.motors[3].kp = 5000.0f;
  c.motors[4].tau = NAN;
  std::vector<uint8_t> f(kLowCommandSize);
  EncodeLowCommand(c, f.data());
  EXPECT_EQ(Le16(f, 10 + 9), 0);
  EXPECT_EQ(Le16(f, 37 + 9), -257);
  EXPECT_EQ(Le16(f, 64 + 9), 32767);
  EXPECT_EQ(Le16(f, 91 + 11), 32767);
  EXPECT_EQ(Le16(f, 118 + 9), 0);
}

TEST(LowCommand, RoundTripsToTheFixedPointResolution) {
  LowCommand c;
  for (int i = 0; i < kMotorSlots; ++i) {
    c.motors[i] = {kModeServo, 0.1f * i, -0.2f * i, 0.37f * i - 3.0f, 1.1f * i, 0.13f * i};
  }
  std::vector<uint8_t> f(kLowCommandSize);
  EncodeLowCommand(c, f.data());
  LowCommand back;
  ASSERT_EQ(DecodeLowCommand(f.data(), f.size(), back), FrameError::kNone);
  for (int i = 0; i < kMotorSlots; ++i) {
    EXPECT_EQ(back.motors[i].q, c.motors[i].q);
    EXPECT_EQ(back.motors[i].dq, c.motors[i].dq);
    EXPECT_NEAR(back.motors[i].tau, c.motors[i].tau, 1.0 / 256);
    EXPECT_NEAR(back.motors[i].kp, c.motors[i].kp, 1.0 / 32);
    EXPECT_NEAR(back.motors[i].kd, c.motors[i].kd, 1.0 / 16);
  }
}

TEST(LowState, FieldsSitAtTheirWireOffsets) {
  LowState s;
  s.imu.quaternion = {0.5f, 0.5f, -0.5f, 0.5f};
  s.imu.gyroscope = {0.1f, 0.2f, 0.3f};
  s.imu.accelerometer = {0.0f, 0.0f, 9.81f};
  s.imu.rpy = {0.01f, 0.02f, 0.03f};
  s.imu.temperature = -5;
  s.motors[11].q = -1.5f;
  s.motors[11].dq = 2.25f;
  s.motors[11].tau_estimate = -4.5f;
  s.motors[11].temperature = 41;
  s.foot_force = {10, 20, 30, -40};
  s.tick = 123456789;
  std::vector<uint8_t> f(kLowStateSize);
  EncodeLowState(s, f.data());
  EXPECT_EQ(f[0], 0xFF);
  EXPECT_EQ(LeFloat(f, 10), 0.5f);
  EXPECT_EQ(LeFloat(f, 22), 0.5f);  // z
  EXPECT_EQ(LeFloat(f, 26), 0.1f);
  EXPECT_EQ(LeFloat(f, 46), 9.81f);  // accelerometer z: 38 + 8
  EXPECT_EQ(LeFloat(f, 58), 0.03f);  // rpy yaw: 50 + 8
  EXPECT_EQ(static_cast<int8_t>(f[62]), -5);
  const size_t o = 63 + 32 * 11;  // 415
  EXPECT_EQ(LeFloat(f, o + 1), -1.5f);
  EXPECT_EQ(LeFloat(f, o + 5), 2.25f);
  EXPECT_EQ(Le16(f, o + 11), -1152);  // -4.5 N m x 256
  EXPECT_EQ(f[o + 23], 41);
  EXPECT_EQ(Le16(f, 703 + 6), -40);
  EXPECT_EQ(Le32(f, 719), 123456789u);
  EXPECT_EQ(Le32(f, 767), Crc32Words(f.data(), 191));

  LowState back;
  ASSERT_EQ(DecodeLowState(f.data(), f.size(), back), FrameError::kNone);
  EXPECT_EQ(back.imu.quaternion, s.imu.quaternion);
  EXPECT_EQ(back.motors[11].tau_estimate, -4.5f);
  EXPECT_EQ(back.motors[11].temperature, 41);
  EXPECT_EQ(back.foot_force, s.foot_force);
  EXPECT_EQ(back.tick, s.tick);
}

TEST(LowState, BadFramesAreRejectedWithTheReason) {
  std::vector<uint8_t> f(kLowStateSize);
  EncodeLowState(LowState{}, f.data());
  LowState s;
  EXPECT_EQ(DecodeLowState(f.data(), f.size() - 1, s), FrameError::kLength);
  EXPECT_EQ(DecodeLowState(f.data(), kLowCommandSize, s), FrameError::kLength);
  std::vector<uint8_t> corrupt = f;
  corrupt[400] ^= 0x10;
  EXPECT_EQ(DecodeLowState(corrupt.data(), corrupt.size(), s), FrameError::kCrc);
  std::vector<uint8_t> high = f;
  high[0] = 0x00;  // a high-level frame
  EXPECT_EQ(DecodeLowState(high.data(), high.size(), s), FrameError::kLevel);
  EXPECT_STREQ(ToString(FrameError::kCrc), "CRC mismatch");
  std::vector<uint8_t> command(kLowCommandSize);
  EncodeLowCommand(LowCommand{}, command.data());
  command[606] ^= 1;
  LowCommand c;
  EXPECT_EQ(DecodeLowCommand(command.data(), command.size(), c), FrameError::kCrc);
}

}  // namespace
}  // namespace flsd::hw
