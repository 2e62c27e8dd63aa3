#include "server/navigation/navigator.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "core/check.h"
#include "skills/runtime/nearest_skill.h"

namespace flsd {
namespace {

template <class... Numbers>
std::string Format(const char* format, Numbers... numbers) {
  char text[192];
  std::snprintf(text, sizeof text, format, static_cast<double>(numbers)...);
  return text;
}

bool IsOurs(const ControllerStatus& s, const NavigationJob& job) {
  return s.task.state == TaskState::kRunning && s.task.request_id == job.request_id &&
         s.task.client_id == job.client_id;
}

// Paths keep a margin over the library's tightest turn both ways: straight segments for a library
// that turns in place, or, unable to turn both ways, cannot follow curves.
double PlanningRadius(const SkillLibrary& library, const NavigationConfig& config) {
  const double radius = TightestTurnOf(library).radius;
  return std::isfinite(radius) ? config.turn_radius_scale * radius : 0.0;
}

// Along such curves, the follower turns no faster than the skills that make the tightest turn.
NavigationConfig WithLibraryTurnRate(NavigationConfig config, const SkillLibrary& library, double turning_radius) {
  if (turning_radius > 0.0) {
    config.follower.max_turn_rate = std::min(config.follower.max_turn_rate, TightestTurnOf(library).yaw_rate);
  }
  return config;
}

}  // namespace

Navigator::Navigator(Controller& controller, const NavigationConfig& config)
    : controller_(controller),
      turning_radius_(PlanningRadius(controller.library(), config)),
      config_(WithLibraryTurnRate(config, controller.library(), turning_radius_)),
      thread_([this] { Run(); }) {}

Navigator::~Navigator() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
    ++generation_;
  }
  wake_.notify_all();
  thread_.join();
}

void Navigator::Start(NavigationJob job) {
  MapRequest request;
  request.job = std::move(job);
  Start(std::move(request));
}

void Navigator::Start(MapRequest request) {
  std::optional<MapRequest> dropped;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    dropped.swap(next_);
    next_ = std::move(request);
    ++generation_;
  }
  if (dropped && dropped->reply) {
    dropped->reply(ReplyStatus::kNotAvailable, "superseded by a later navigate before its map was read", 0);
  }
  wake_.notify_all();
}

void Navigator::Cancel() {
  std::optional<MapRequest> dropped;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    dropped.swap(next_);
    ++generation_;
  }
  if (dropped && dropped->reply) {
    dropped->reply(ReplyStatus::kNotAvailable, "superseded by a later request before its map was read", 0);
  }
}

std::vector<double> Navigator::Path() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return path_;
}

bool Navigator::Superseded(uint64_t generation) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return quit_ || generation_ != generation;
}

void Navigator::Run() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!quit_) {
    wake_.wait(lock, [&] { return quit_ || next_.has_value(); });
    if (quit_) break;
    MapRequest request = std::move(*next_);
    next_.reset();
    const uint64_t generation = generation_;  // read with the job, so a newer Start is seen
    lock.unlock();
    const NavigationJob& job = request.job;
    try {
      if (!request.reply || Accept(request, generation)) Navigate(job, generation);
    } catch (const std::exception& e) {  // never let a navigation take the server down
      Finish(job, TaskState::kCancelled, std::string("navigation failed: ") + e.what());
    }
    lock.lock();
    path_.clear();
  }
}

bool Navigator::Accept(MapRequest& request, uint64_t generation) {
  try {
    request.job.map = Map2D::Parse(request.map_yaml, "the request's map");
  } catch (const InputError& e) {
    request.reply(ReplyStatus::kInvalidArgument, e.what(), 0);
    return false;
  }
  uint64_t ticket = 0;
  bool superseded = false;
  {
    // Held while submitting: a Cancel() either comes first and is seen here, or comes after and
    // is followed by its own request, which then overrides this task in the controller.
    std::lock_guard<std::mutex> lock(mutex_);
    superseded = quit_ || generation_ != generation;
    if (!superseded) ticket = controller_.Submit(request.task);
  }
  if (superseded) {
    request.reply(ReplyStatus::kNotAvailable, "superseded by a later request while its map was read", 0);
  } else if (ticket == 0) {
    request.reply(ReplyStatus::kInternal, "the control queue is full; retry", 0);
  } else {
    request.reply(ReplyStatus::kOk, request.accepted, ticket);
  }
  return ticket != 0;
}

bool Navigator::Plan(const NavigationJob& job, const Eigen::Vector2d& from, double yaw, PlannedPath& path) {
  PlannerOptions options;
  options.turning_radius = turning_radius_;
  options.time_limit = config_.planning_time;
  options.waypoint_spacing = config_.waypoint_spacing;
  options.clearance_margin = config_.clearance_margin;
  path = PlanPath(job.map, from, job.goal, options, yaw);
  if (path.status != PlannedPath::Status::kFound) {
    Finish(job, TaskState::kNoPath, path.message);
    return false;
  }
  std::vector<double> flat;
  for (const Eigen::Vector2d& p : path.waypoints) flat.insert(flat.end(), {p.x(), p.y()});
  std::lock_guard<std::mutex> lock(mutex_);
  path_ = std::move(flat);
  return true;
}

void Navigator::Navigate(const NavigationJob& job, uint64_t generation) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const auto period = std::chrono::duration<double>(1.0 / config_.rate_hz);

  PlannedPath path;
  const ControllerStatus begin = controller_.status();
  if (!Plan(job, begin.state.base_position.head<2>(), begin.state.Yaw(), path)) return;
  spdlog::info("navigate to ({:.2f}, {:.2f}): {} waypoints, {:.2f} m, turning radius {:.2f} m, planned in {:.0f} ms",
               job.goal.x(), job.goal.y(), path.waypoints.size(), path.length, path.turning_radius,
               1e3 * path.planning_seconds);
  WaypointFollower follower(path.waypoints, config_.follower);
  int replans = 0;
  double last_replan = -HUGE_VAL;  // s since the start
  bool seen = false;  // the controller applies the task's request at its next tick
  for (Clock::time_point next = Clock::now(); !Superseded(generation); next += std::chrono::duration_cast<Clock::duration>(period)) {
    std::this_thread::sleep_until(next);
    next = std::max(next, Clock::now());  // after a long replan, go on from now rather than catch up
    const ControllerStatus status = controller_.status();
    const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    if (!IsOurs(status, job)) {
      if (seen || elapsed > 1.0) return;  // ended elsewhere: stop, damp, safety, lease, preemption
      continue;
    }
    seen = true;
    if (elapsed > job.timeout) {
      const double left = (job.goal - status.state.base_position.head<2>()).norm();
      Finish(job, TaskState::kTimeout,
             Format("timeout after %.0f s, %.2f m from the goal, %.0f replans", elapsed, left, replans));
      return;
    }
    if (status.mode != Mode::kNavigate) continue;  // still standing up
    const Eigen::Vector2d position = status.state.base_position.head<2>();
    const double free_clearance = job.map.Clearance(position) - job.map.robot_radius;
    const FollowerCommand command = follower.Update(position, status.state.Yaw(), free_clearance);
    if (command.reached) {
      Finish(job, TaskState::kSucceeded,
             Format("reached (%.2f, %.2f), %.2f m from the goal, %.0f replans", position.x(), position.y(),
                    (job.goal - position).norm(), replans));
      return;
    }
    // Plan again when the robot strays off the path, or away from it into the robot's radius of
    // an obstacle (at most once a second there: the new path leads out, and walking out takes
    // time; a path that itself runs along the radius is no reason).
    const bool inside = free_clearance < -config_.replan_inside &&
                        command.distance_to_path > config_.follower.goal_tolerance && elapsed - last_replan > 1.0;
    if (command.off_path || inside) {
      ++replans;
      last_replan = elapsed;
      spdlog::info("navigate: {}; replanning ({})",
                   inside ? Format("%.2f m inside an obstacle's margin", -free_clearance)
                          : Format("%.2f m off the path", command.distance_to_path),
                   replans);
      Steer(job, Eigen::Vector3d::Zero(), "replanning");  // hold still while planning
      if (!Plan(job, position, status.state.Yaw(), path)) return;
      follower = WaypointFollower(path.waypoints, config_.follower);
      continue;
    }
    Steer(job, command.velocity,
          Format("%.2f m to go along the path, %.0f replans", command.remaining, replans));
  }
}

void Navigator::Steer(const NavigationJob& job, const Eigen::Vector3d& velocity, const std::string& progress) {
  ControlRequest update;
  update.kind = ControlRequest::Kind::kVelocityUpdate;
  update.client_id = job.client_id;
  update.request_id = job.request_id;
  update.velocity = {velocity.x(), velocity.y(), velocity.z()};
  SetText(update.reason, progress.c_str());
  controller_.Submit(update);  // a full queue drops one update; the next one comes within a period
}

void Navigator::Finish(const NavigationJob& job, TaskState state, const std::string& message) {
  ControlRequest stop;
  stop.kind = ControlRequest::Kind::kStop;
  stop.client_id = job.client_id;
  stop.request_id = job.request_id;
  stop.scope = ControlRequest::Scope::kTask;
  stop.stop_state = state;
  SetText(stop.reason, message.c_str());
  // Urgent: the end of a navigation must not wait behind (or be lost to) a full queue.
  controller_.SubmitUrgent(stop);
  spdlog::info("navigate: {}", message);
}

}  // namespace flsd
