#include "server/request_queue.h"

#include <algorithm>
#include <utility>

namespace flsd {

bool RequestQueue::Submit(const ControlRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (count_ == kSize) return false;
  queue_[(head_ + count_) % kSize] = request;
  ++count_;
  return true;
}

void RequestQueue::SubmitUrgent(const ControlRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (request.kind == ControlRequest::Kind::kDamp) {
    urgent_damp_ = request;
    have_urgent_damp_ = true;
  } else if (urgent_stop_count_ < kUrgentStops) {
    urgent_stops_[urgent_stop_count_++] = request;
  } else {  // a flood of hand-overs within one tick: stop more than was asked, never less
    ControlRequest& last = urgent_stops_[kUrgentStops - 1];
    last = request;
    last.scope = ControlRequest::Scope::kAny;
  }
}

bool RequestQueue::TakeQueued(ControlRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (count_ == 0) return false;
  request = queue_[head_];
  head_ = (head_ + 1) % kSize;
  --count_;
  return true;
}

int RequestQueue::TakeUrgent(bool& have_damp) {
  std::lock_guard<std::mutex> lock(mutex_);
  have_damp = std::exchange(have_urgent_damp_, false);
  taken_damp_ = urgent_damp_;
  const int stops = std::exchange(urgent_stop_count_, 0);
  std::copy_n(urgent_stops_.begin(), stops, taken_stops_.begin());
  return stops;
}

}  // namespace flsd
