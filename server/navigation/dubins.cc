#include "server/navigation/dubins.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/check.h"

namespace flsd {
namespace {

double WrapTwoPi(double angle) {
  const double wrapped = std::fmod(angle, 2.0 * M_PI);
  return wrapped < 0.0 ? wrapped + 2.0 * M_PI : wrapped;
}

using Turn = DubinsPath::Turn;

// A squared length this far below zero is rounding: the word just joins the poses.
constexpr double kRounding = 1e-9;

struct Word {
  std::array<Turn, 3> turns;
  std::array<double, 3> lengths;  // in turning radii: radians of an arc, radii of a straight
};

// Each word's closed form with the radius 1, the start at the origin heading `a` and the goal at
// (d, 0) heading `b`; none where the word cannot join them.
std::optional<Word> Solve(const std::array<Turn, 3>& turns, double d, double a, double b) {
  const double sa = std::sin(a), sb = std::sin(b), ca = std::cos(a), cb = std::cos(b), cab = std::cos(a - b);
  constexpr Turn L = Turn::kLeft, S = Turn::kStraight, R = Turn::kRight;
  if (turns == std::array<Turn, 3>{L, S, L}) {
    const double p2 = 2.0 + d * d - 2.0 * cab + 2.0 * d * (sa - sb);
    if (p2 < -kRounding) return std::nullopt;
    const double theta = std::atan2(cb - ca, d + sa - sb);
    return Word{turns, {WrapTwoPi(theta - a), std::sqrt(std::max(p2, 0.0)), WrapTwoPi(b - theta)}};
  }
  if (turns == std::array<Turn, 3>{R, S, R}) {
    const double p2 = 2.0 + d * d - 2.0 * cab + 2.0 * d * (sb - sa);
    if (p2 < -kRounding) return std::nullopt;
    const double theta = std::atan2(ca - cb, d - sa + sb);
    return Word{turns, {WrapTwoPi(a - theta), std::sqrt(std::max(p2, 0.0)), WrapTwoPi(theta - b)}};
  }
  if (turns == std::array<Turn, 3>{L, S, R}) {
    const double p2 = -2.0 + d * d + 2.0 * cab + 2.0 * d * (sa + sb);
    if (p2 < -kRounding) return std::nullopt;
    const double p = std::sqrt(std::max(p2, 0.0)), theta = std::atan2(-ca - cb, d + sa + sb) - std::atan2(-2.0, p);
    return Word{turns, {WrapTwoPi(theta - a), p, WrapTwoPi(theta - b)}};
  }
  if (turns == std::array<Turn, 3>{R, S, L}) {
    const double p2 = -2.0 + d * d + 2.0 * cab - 2.0 * d * (sa + sb);
    if (p2 < -kRounding) return std::nullopt;
    const double p = std::sqrt(std::max(p2, 0.0)), theta = std::atan2(ca + cb, d - sa - sb) - std::atan2(2.0, p);
    return Word{turns, {WrapTwoPi(a - theta), p, WrapTwoPi(b - theta)}};
  }
  if (turns == std::array<Turn, 3>{R, L, R}) {
    const double c = (6.0 - d * d + 2.0 * cab + 2.0 * d * (sa - sb)) / 8.0;
    if (std::abs(c) > 1.0) return std::nullopt;
    const double p = WrapTwoPi(2.0 * M_PI - std::acos(c));
    const double t = WrapTwoPi(a - std::atan2(ca - cb, d - sa + sb) + p / 2.0);
    return Word{turns, {t, p, WrapTwoPi(a - b - t + p)}};
  }
  // L R L
  const double c = (6.0 - d * d + 2.0 * cab + 2.0 * d * (sb - sa)) / 8.0;
  if (std::abs(c) > 1.0) return std::nullopt;
  const double p = WrapTwoPi(2.0 * M_PI - std::acos(c));
  const double t = WrapTwoPi(-a - std::atan2(ca - cb, d + sa - sb) + p / 2.0);
  return Word{turns, {t, p, WrapTwoPi(b - a - t + p)}};
}

// The pose after `s` metres of one piece from `pose`.
Pose2 Advance(const Pose2& pose, Turn turn, double s, double radius) {
  Pose2 next = pose;
  switch (turn) {
    case Turn::kStraight:
      next.x += s * std::cos(pose.yaw);
      next.y += s * std::sin(pose.yaw);
      break;
    case Turn::kLeft:  // about the centre at the robot's left
      next.yaw = pose.yaw + s / radius;
      next.x += radius * (std::sin(next.yaw) - std::sin(pose.yaw));
      next.y -= radius * (std::cos(next.yaw) - std::cos(pose.yaw));
      break;
    case Turn::kRight:
      next.yaw = pose.yaw - s / radius;
      next.x -= radius * (std::sin(next.yaw) - std::sin(pose.yaw));
      next.y += radius * (std::cos(next.yaw) - std::cos(pose.yaw));
      break;
  }
  return next;
}

}  // namespace

DubinsPath::DubinsPath(const Pose2& from, const Pose2& to, double radius) : from_(from), radius_(radius) {
  FLSD_DEMAND(radius > 0.0);
  const double dx = to.x - from.x, dy = to.y - from.y;
  const double d = std::hypot(dx, dy) / radius, direction = std::atan2(dy, dx);
  const double a = WrapTwoPi(from.yaw - direction), b = WrapTwoPi(to.yaw - direction);
  constexpr Turn L = Turn::kLeft, S = Turn::kStraight, R = Turn::kRight;
  length_ = HUGE_VAL;
  for (const std::array<Turn, 3>& turns : {std::array<Turn, 3>{L, S, L}, {R, S, R}, {L, S, R}, {R, S, L}, {R, L, R}, {L, R, L}}) {
    const std::optional<Word> word = Solve(turns, d, a, b);
    if (!word) continue;
    const double length = radius * (word->lengths[0] + word->lengths[1] + word->lengths[2]);
    if (length < length_) {
      length_ = length;
      word_ = word->turns;
      for (int i = 0; i < 3; ++i) segment_[i] = radius * word->lengths[i];
    }
  }
  FLSD_DEMAND(std::isfinite(length_));  // LSL or RSR always joins two poses
}

Pose2 DubinsPath::At(double s) const {
  s = std::clamp(s, 0.0, length_);
  Pose2 pose = from_;
  for (int i = 0; i < 3 && s > 0.0; ++i) {
    const double piece = std::min(s, segment_[i]);
    pose = Advance(pose, word_[i], piece, radius_);
    s -= piece;
  }
  return pose;
}

}  // namespace flsd
