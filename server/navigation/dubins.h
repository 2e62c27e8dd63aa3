#pragma once
// Shortest paths of a vehicle that moves forward only and turns no tighter than a radius (Dubins,
// 1957): between two poses, one of six words of three arcs or straights, LSL, RSR, LSR, RSL, RLR
// or LRL (Shkel and Lumelsky, 2001, give each word's closed form). Written here rather than taken
// from OMPL's DubinsStateSpace, whose Debian build asserts (aborts) on rounding in some words:
// skilld must not die mid-walk.

#include <Eigen/Core>

#include <array>

namespace flsd {

struct Pose2 {
  double x = 0.0, y = 0.0, yaw = 0.0;  // m, m, rad
};

class DubinsPath {
 public:
  enum class Turn { kLeft, kStraight, kRight };

  // The shortest path from `from` to `to` turning at `radius` (m, > 0).
  DubinsPath(const Pose2& from, const Pose2& to, double radius);

  double length() const { return length_; }  // m
  // The pose `s` metres along the path (clamped to [0, length]).
  Pose2 At(double s) const;
  const std::array<Turn, 3>& word() const { return word_; }

 private:
  Pose2 from_;
  double radius_;
  std::array<Turn, 3> word_{};
  std::array<double, 3> segment_{};  // m along each of the word's three pieces
  double length_ = 0.0;
};

}  // namespace flsd
