#include "server/navigation/waypoint_follower.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace flsd {

WaypointFollower::WaypointFollower(std::vector<Eigen::Vector2d> waypoints, const FollowerConfig& config)
    : waypoints_(std::move(waypoints)), config_(config) {
  FLSD_DEMAND(!waypoints_.empty());
  arc_.push_back(0.0);
  for (size_t i = 1; i < waypoints_.size(); ++i) arc_.push_back(arc_.back() + (waypoints_[i] - waypoints_[i - 1]).norm());
}

FollowerCommand WaypointFollower::Update(const Eigen::Vector2d& position, double yaw, double free_clearance) {
  FollowerCommand out;
  // The closest point on the path at or beyond the progress so far (so loops are not cut short).
  double best = HUGE_VAL, best_arc = progress_;
  for (size_t i = 1; i < waypoints_.size(); ++i) {
    if (arc_[i] < progress_) continue;
    const Eigen::Vector2d a = waypoints_[i - 1], ab = waypoints_[i] - a;
    const double length = ab.norm();
    double t = length > 0.0 ? std::clamp((position - a).dot(ab) / (length * length), 0.0, 1.0) : 0.0;
    t = std::max(t, length > 0.0 ? (progress_ - arc_[i - 1]) / length : 0.0);
    const double d = (position - (a + t * ab)).norm();
    if (d < best) {
      best = d;
      best_arc = arc_[i - 1] + t * length;
    }
  }
  if (waypoints_.size() == 1) best = (position - waypoints_[0]).norm();
  progress_ = best_arc;
  out.distance_to_path = best;
  out.remaining = arc_.back() - progress_ + (position - waypoints_.back()).norm() * (progress_ >= arc_.back());
  out.off_path = best > config_.replan_distance;
  if ((position - waypoints_.back()).norm() < config_.goal_tolerance) {
    out.reached = true;
    return out;
  }

  // The lookahead point, lookahead metres beyond the closest point.
  const double target_arc = std::min(arc_.back(), progress_ + config_.lookahead);
  Eigen::Vector2d target = waypoints_.back();
  for (size_t i = 1; i < waypoints_.size(); ++i) {
    if (arc_[i] >= target_arc) {
      const double span = arc_[i] - arc_[i - 1];
      const double t = span > 0.0 ? (target_arc - arc_[i - 1]) / span : 1.0;
      target = waypoints_[i - 1] + t * (waypoints_[i] - waypoints_[i - 1]);
      break;
    }
  }
  const Eigen::Vector2d to_target = target - position;
  const double c = std::cos(yaw), s = std::sin(yaw);
  const Eigen::Vector2d body(c * to_target.x() + s * to_target.y(), -s * to_target.x() + c * to_target.y());
  const double heading_error = std::atan2(body.y(), body.x());
  out.velocity.z() = std::clamp(config_.heading_gain * heading_error, -config_.max_turn_rate, config_.max_turn_rate);
  if (std::abs(heading_error) > config_.turn_in_place_above) return out;  // turn first
  // Slow down over the last half metre so as not to overshoot the goal, and near obstacles.
  const double room = config_.slow_clearance > 0.0 ? std::clamp(free_clearance / config_.slow_clearance, 0.0, 1.0) : 1.0;
  const double share = config_.min_speed_share + (1.0 - config_.min_speed_share) * room;
  double speed = share * std::min(config_.max_speed, config_.max_speed * (position - waypoints_.back()).norm() / 0.5);
  // No faster than the arc through the target point (curvature 2 sin(error) / distance) can be
  // walked turning at max_turn_rate: a faster command would pick a wider arc, which overshoots.
  const double curvature = 2.0 * std::abs(body.y()) / std::max(body.squaredNorm(), 1e-12);
  if (curvature > 0.0) speed = std::min(speed, config_.max_turn_rate / curvature);
  if (body.norm() > 1e-9) out.velocity.head<2>() = body.normalized() * speed;
  return out;
}

}  // namespace flsd
