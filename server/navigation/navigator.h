#pragma once
// navigate(goal, map): plans with OMPL on its own thread (never on the request or control
// thread), then steers the controller's velocity task along the waypoints, replanning when the
// robot strays, and ends the task as reached, no path or timeout. A navigation is a velocity task
// (Controller, MODE_NAVIGATE) whose command this thread updates; whoever ends that task
// (stop, damp, a safety stop, a new request, a lapsed lease) thereby ends the navigation.

#include <Eigen/Core>

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "api/modes.h"
#include "navigation_map/map2d.h"
#include "server/controller.h"
#include "server/navigation/path_planner.h"

namespace flsd {

struct NavigationJob {
  ClientId client_id{};
  uint64_t request_id = 0;
  Eigen::Vector2d goal = Eigen::Vector2d::Zero();
  Map2D map;
  double timeout = 120.0;  // s, standing up included
};

// A navigate request whose map came with it: the map is read on the navigator's thread (reading
// costs time, and the request thread must stay free for the emergency stop); only then is the
// controller's task submitted and the request answered.
struct MapRequest {
  NavigationJob job;  // job.map is read from map_yaml
  std::string map_yaml;
  ControlRequest task;   // the controller's task for the job
  std::string accepted;  // the reply's message once it is under way
  // `ticket`: the submitted task's (Controller::Submit), for an OK reply to wait for; 0 otherwise.
  std::function<void(ReplyStatus, const std::string&, uint64_t ticket)> reply;
};

class Navigator {
 public:
  // `controller` must outlive the navigator.
  Navigator(Controller& controller, const NavigationConfig& config);
  ~Navigator();
  Navigator(const Navigator&) = delete;
  Navigator& operator=(const Navigator&) = delete;

  // Takes over from any navigation in progress. The controller's task for the job must have been
  // submitted first (a kVelocity request with `navigate` set and the job's ids).
  void Start(NavigationJob job);
  // Takes over likewise, but reads the map first (see MapRequest); a map that does not parse is
  // answered with STATUS_INVALID_ARGUMENT and nothing moves.
  void Start(MapRequest request);
  // Ends any navigation in progress and drops one whose map is still being read (answered as
  // superseded). Call it before submitting any other motion, so that a navigation accepted
  // earlier never starts after it.
  void Cancel();

  // The path being followed (empty when none), x0 y0 x1 y1 ..., for telemetry.
  std::vector<double> Path() const;

 private:
  void Run();
  // Reads the map of `request`, submits its task unless superseded, and answers it; whether it runs.
  bool Accept(MapRequest& request, uint64_t generation);
  void Navigate(const NavigationJob& job, uint64_t generation);
  bool Plan(const NavigationJob& job, const Eigen::Vector2d& from, double yaw, PlannedPath& path);
  void Finish(const NavigationJob& job, TaskState state, const std::string& message);
  void Steer(const NavigationJob& job, const Eigen::Vector3d& velocity, const std::string& progress);
  bool Superseded(uint64_t generation) const;

  Controller& controller_;
  const double turning_radius_;  // m the planned paths keep to (PlannerOptions)
  NavigationConfig config_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<MapRequest> next_;  // a job whose task is submitted has an empty map_yaml and no reply
  uint64_t generation_ = 0;  // counts Start() calls; a job stops when a newer one arrives
  bool quit_ = false;
  std::vector<double> path_;
  std::thread thread_;
};

}  // namespace flsd
