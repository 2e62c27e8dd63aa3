#pragma once
// navigate(goal, map): plans with OMPL on its own thread (never on the request or control
// thread), then steers the controller's velocity task along the waypoints, replanning when the
// robot strays, and ends the task as reached, no path or timeout. A navigation is a velocity task
// (Controller, MODE_NAVIGATE) whose command this thread updates; whoever ends that task
// (stop, damp, a safety stop, a new request, a lapsed lease) thereby ends the navigation.

#include <Eigen/Core>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "server/controller.h"
#include "server/navigation/map2d.h"
#include "server/navigation/path_planner.h"

namespace flsd {

struct NavigationJob {
  ClientId client_id{};
  uint64_t request_id = 0;
  Eigen::Vector2d goal = Eigen::Vector2d::Zero();
  Map2D map;
  double timeout = 120.0;  // s, standing up included
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

  // The path being followed (empty when none), x0 y0 x1 y1 ..., for telemetry.
  std::vector<double> Path() const;

 private:
  void Run();
  void Navigate(const NavigationJob& job, uint64_t generation);
  bool Plan(const NavigationJob& job, const Eigen::Vector2d& from, PlannedPath& path);
  void Finish(const NavigationJob& job, flsd_msgs_TaskState state, const std::string& message);
  void Steer(const NavigationJob& job, const Eigen::Vector3d& velocity, const std::string& progress);
  bool Superseded(uint64_t generation) const;

  Controller& controller_;
  NavigationConfig config_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<NavigationJob> next_;
  uint64_t generation_ = 0;  // counts Start() calls; a job stops when a newer one arrives
  bool quit_ = false;
  std::vector<double> path_;
  std::thread thread_;
};

}  // namespace flsd
