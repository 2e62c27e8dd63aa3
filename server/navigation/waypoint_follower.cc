#include "server/navigation/waypoint_follower.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace flsd {
namespace {

// The direction of `world` (a vector in the world frame) in the body frame of a robot heading `yaw`.
Eigen::Vector2d ToBody(const Eigen::Vector2d& world, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {c * world.x() + s * world.y(), -s * world.x() + c * world.y()};
}

double Bearing(const Eigen::Vector2d& body) { return std::atan2(body.y(), body.x()); }

}  // namespace

WaypointFollower::WaypointFollower(std::vector<Eigen::Vector2d> waypoints, const FollowerConfig& config)
    : waypoints_(std::move(waypoints)), config_(config) {
  FLSD_DEMAND(!waypoints_.empty());
  arc_.push_back(0.0);
  for (size_t i = 1; i < waypoints_.size(); ++i) arc_.push_back(arc_.back() + (waypoints_[i] - waypoints_[i - 1]).norm());
  if (config_.backward_speed > 0.0) {
    for (size_t first = 0; first + 1 < waypoints_.size();) {
      size_t last = first + 1;
      while (last + 1 < waypoints_.size() && Straight(first, last + 1)) ++last;
      stretch_ends_.push_back(last);
      first = last;
    }
  }
}

bool WaypointFollower::Straight(size_t first, size_t last) const {
  const Eigen::Vector2d a = waypoints_[first], ab = waypoints_[last] - a;
  const double length = ab.norm();
  for (size_t i = first + 1; i < last; ++i) {
    const Eigen::Vector2d ap = waypoints_[i] - a;
    const double along = length > 0.0 ? ap.dot(ab) / length : 0.0;
    const double across = length > 0.0 ? std::abs(ab.x() * ap.y() - ab.y() * ap.x()) / length : ap.norm();
    if (across > kStraightTolerance || along < 0.0 || along > length) return false;
  }
  return true;
}

void WaypointFollower::Face(size_t index, const Eigen::Vector2d& position, double yaw) {
  const Eigen::Vector2d to_end = waypoints_[stretch_ends_[index]] - position;
  const double ahead = std::abs(Bearing(ToBody(to_end, yaw)));  // rad to turn to face the end
  const double length = to_end.norm();
  const double forward = ahead / config_.max_turn_rate + length / config_.max_speed;
  const double backward = (M_PI - ahead) / config_.max_turn_rate + length / config_.backward_speed;
  stretch_ = index;
  backward_ = backward < forward;
  turning_ = 0;
  aligned_ = false;
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

  // The stretch the robot is on: the first whose end is more than a lookahead further on (the
  // next one's facing is chosen that early, since a fast walk carries the robot on).
  if (!stretch_ends_.empty()) {
    size_t index = 0;
    while (index + 1 < stretch_ends_.size() && arc_[stretch_ends_[index]] - config_.lookahead <= progress_) ++index;
    if (index != stretch_) Face(index, position, yaw);
    out.backward = backward_;
  }
  // Facing away, it first turns its back to the stretch's end, unless that end is within a
  // lookahead, and then walks: once a stretch, since turning again as the gallop sets off (its
  // first strides swing the heading 0.2 rad) switched between turns and gallop every few ticks
  // and threw the robot. Should it stray, the navigator plans again, and it aligns afresh.
  if (backward_) {
    const Eigen::Vector2d to_end = ToBody(waypoints_[stretch_ends_[stretch_]] - position, yaw);
    const double off = std::remainder(Bearing(to_end) - M_PI, 2.0 * M_PI);
    // Walking straight back, it passes the end this far to the side (or the end is ahead of it).
    const double miss = to_end.x() < 0.0 ? std::abs(to_end.y()) : HUGE_VAL;
    if (to_end.norm() <= config_.lookahead) {
      turning_ = 0;
      aligned_ = true;
    } else if (!aligned_ && turning_ == 0) {
      if (std::abs(off) > config_.backward_align && miss > config_.goal_tolerance) turning_ = off > 0.0 ? 1 : -1;
      aligned_ = turning_ == 0;
    } else if (turning_ * off <= config_.turn_lead) {
      turning_ = 0;  // aligned, once the turn has run on
      aligned_ = true;
    }
    if (turning_ != 0) {
      out.velocity.z() = turning_ * config_.max_turn_rate;
      return out;
    }
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
  const Eigen::Vector2d body = ToBody(target - position, yaw);
  const double heading_error = std::remainder(Bearing(body) - (backward_ ? M_PI : 0.0), 2.0 * M_PI);
  out.velocity.z() = std::clamp(config_.heading_gain * heading_error, -config_.max_turn_rate, config_.max_turn_rate);
  if (std::abs(heading_error) > config_.turn_in_place_above) return out;  // turn first
  // Slow down over the last half metre (at max_speed; a faster gait over as many seconds) so as
  // not to overshoot the goal, nor reach it at a gallop, which the stand after it cannot catch; and
  // near obstacles.
  const double room = config_.slow_clearance > 0.0 ? std::clamp(free_clearance / config_.slow_clearance, 0.0, 1.0) : 1.0;
  const double share = config_.min_speed_share + (1.0 - config_.min_speed_share) * room;
  const double top = backward_ ? config_.backward_speed : config_.max_speed;
  const double slowing = 0.5 * std::max(1.0, top / config_.max_speed);  // m
  double speed = share * std::min(top, top * (position - waypoints_.back()).norm() / slowing);
  // No faster than the arc through the target point (curvature 2 sin(error) / distance) can be
  // walked turning at max_turn_rate: a faster command would pick a wider arc, which overshoots.
  // (Backward, the robot turns in place instead.)
  const double curvature = 2.0 * std::abs(body.y()) / std::max(body.squaredNorm(), 1e-12);
  if (curvature > 0.0 && !backward_) speed = std::min(speed, config_.max_turn_rate / curvature);
  if (body.norm() > 1e-9) out.velocity.head<2>() = body.normalized() * speed;
  return out;
}

}  // namespace flsd
