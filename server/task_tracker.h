#pragma once
// The long call the controller runs for a client (execute_skill, track_velocity, navigate) and how
// it stands, as RobotState.task publishes it.

#include <array>
#include <cstdint>

#include "server/control_request.h"

namespace flsd {

struct TaskStatus {
  ClientId client_id{};
  uint64_t request_id = 0;
  std::array<char, 24> call{};
  TaskState state = TaskState::kNone;
  double elapsed = 0.0;    // s since the request was taken
  double remaining = 0.0;  // s until it ends (standing up included)
  FixedText message{};
};

class TaskTracker {
 public:
  // `request`'s task, named `call`, runs from control tick `tick`.
  void Start(const ControlRequest& request, const char* call, uint64_t tick);
  // Ends the running task (if any) as `state`, saying why.
  void End(TaskState state, const char* message);
  bool running() const { return status_.state == TaskState::kRunning; }
  // Whether `request` names the running task (client and request id).
  bool IsRunning(const ControlRequest& request) const;
  // Whether a stop applies, by its scope: to whatever runs, to the client's task (from before
  // the stop's request_id, when it has one), or to one task.
  bool StoppedBy(const ControlRequest& stop) const;
  void SetMessage(const FixedText& message) { status_.message = message; }
  // At control tick `tick`, with `ticks_left` before the running task ends.
  void Update(uint64_t tick, int ticks_left, double control_period);
  const TaskStatus& status() const { return status_; }

 private:
  TaskStatus status_;
  uint64_t start_tick_ = 0;
};

}  // namespace flsd
