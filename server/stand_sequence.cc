#include "server/stand_sequence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "robot/state_limits.h"

namespace flsd {
namespace {

int Ticks(double seconds) { return static_cast<int>(std::lround(seconds / a1::kControlDt)); }

}  // namespace

void StandSequence::StartBrake() { brake_ticks_left_ = flsd::Ticks(config_.stand_brake_time); }

bool StandSequence::TakeBrakeTick() {
  if (brake_ticks_left_ <= 0) return false;
  --brake_ticks_left_;
  return true;
}

void StandSequence::MoveTo(const RobotState& robot, const a1::JointArray<double>& to) {
  from_ = robot.joint_position;
  to_ = to;
  ticks_ = 0;
  unverified_ticks_ = 0;
  total_ticks_ = Ticks(from_, to);
  move_ticks_ = total_ticks_ - flsd::Ticks(kSettle);
}

int StandSequence::Ticks(const a1::JointArray<double>& from, const a1::JointArray<double>& to) const {
  double farthest = 0.0;
  for (int j = 0; j < a1::kNumJoints; ++j) farthest = std::max(farthest, std::abs(to[j] - from[j]));
  return std::max(1, flsd::Ticks(farthest / config_.stand_joint_speed)) + flsd::Ticks(kSettle);
}

JointCommand StandSequence::Command() {
  const double s = std::min(1.0, static_cast<double>(ticks_) / move_ticks_);
  a1::JointArray<double> target;
  for (int j = 0; j < a1::kNumJoints; ++j) target[j] = from_[j] + s * (to_[j] - from_[j]);
  if (ticks_ < total_ticks_) ++ticks_;
  JointCommand command;
  command.position = target;
  command.kp.fill(config_.stand_kp);
  command.kd.fill(config_.stand_kd);
  return command;
}

StandSequence::Verdict StandSequence::Verify(const RobotState& robot) {
  if (Standing(robot)) {
    unverified_ticks_ = 0;
    return Verdict::kStanding;
  }
  if (++unverified_ticks_ < flsd::Ticks(config_.stand_check.timeout)) return Verdict::kSettling;
  if (recoveries_ < config_.stand_check.max_recoveries) {
    ++recoveries_;
    return Verdict::kRecover;
  }
  unverified_ticks_ = 0;
  return Verdict::kFailed;
}

bool StandSequence::Standing(const RobotState& robot, char* why, std::size_t size) const {
  const StandCheckConfig& c = config_.stand_check;
  int worst_error = 0, fastest = 0;
  for (int j = 1; j < a1::kNumJoints; ++j) {
    const auto error = [&](int k) { return std::abs(robot.joint_position[k] - a1::kDefaultJointPos[k]); };
    if (!(error(j) <= error(worst_error))) worst_error = j;  // a NaN is the worst
    if (!(std::abs(robot.joint_velocity[j]) <= std::abs(robot.joint_velocity[fastest]))) fastest = j;
  }
  const double tilt = TiltOf(robot);
  const double height = robot.base_position.z();
  const double error = std::abs(robot.joint_position[worst_error] - a1::kDefaultJointPos[worst_error]);
  const double speed = std::abs(robot.joint_velocity[fastest]);
  const double turn_rate = robot.base_angular_velocity.norm();
  const bool upright = tilt <= c.max_tilt;
  const bool high = c.min_base_height <= 0.0 || height >= c.min_base_height;
  const bool posed = error <= c.max_joint_error;
  const bool still = speed <= c.max_joint_speed && turn_rate <= c.max_turn_rate;
  if (upright && high && posed && still) return true;
  if (why == nullptr || size == 0) return false;
  why[0] = '\0';
  std::size_t used = 0;
  const auto add = [&](const char* format, auto... args) {
    const int n = std::snprintf(why + used, size - used, format, used == 0 ? "" : "; ", args...);
    if (n > 0) used = std::min(size - 1, used + static_cast<std::size_t>(n));
  };
  if (!upright) add("%stilt %.2f rad > %.2f", tilt, c.max_tilt);
  if (!high) add("%sbase %.3f m < %.3f", height, c.min_base_height);
  if (!posed) add("%s%s %.2f rad off the stand > %.2f", a1::kJointNames[worst_error], error, c.max_joint_error);
  if (!(speed <= c.max_joint_speed)) add("%s%s at %.1f rad/s > %.1f", a1::kJointNames[fastest], speed, c.max_joint_speed);
  if (!(turn_rate <= c.max_turn_rate)) add("%sbase turning at %.2f rad/s > %.2f", turn_rate, c.max_turn_rate);
  return false;
}

}  // namespace flsd
