#include "server/task_tracker.h"

namespace flsd {

void TaskTracker::Start(const ControlRequest& request, const char* call, uint64_t tick) {
  status_ = TaskStatus{};
  status_.client_id = request.client_id;
  status_.request_id = request.request_id;
  SetText(status_.call, call);
  status_.state = TaskState::kRunning;
  start_tick_ = tick;
}

void TaskTracker::End(TaskState state, const char* message) {
  if (!running()) return;
  status_.state = state;
  status_.remaining = 0.0;
  SetText(status_.message, message);
}

bool TaskTracker::IsRunning(const ControlRequest& request) const {
  return running() && status_.client_id == request.client_id && status_.request_id == request.request_id;
}

bool TaskTracker::StoppedBy(const ControlRequest& stop) const {
  switch (stop.scope) {
    case ControlRequest::Scope::kAny: return true;
    case ControlRequest::Scope::kClient:
      return running() && status_.client_id == stop.client_id &&
             (stop.request_id == 0 || status_.request_id < stop.request_id);
    case ControlRequest::Scope::kTask: return IsRunning(stop);
  }
  return false;
}

void TaskTracker::Update(uint64_t tick, int ticks_left, double control_period) {
  if (!running()) return;
  status_.elapsed = static_cast<double>(tick - start_tick_) * control_period;
  status_.remaining = ticks_left * control_period;
}

}  // namespace flsd
