#include "server/request_queue.h"

#include <algorithm>
#include <utility>

namespace flsd {

uint64_t RequestQueue::Submit(const ControlRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (count_ == kSize) return 0;
  queue_[(head_ + count_) % kSize] = request;
  ++count_;
  return ++last_ticket_;
}

uint64_t RequestQueue::SubmitUrgent(const ControlRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (request.kind == ControlRequest::Kind::kDamp) {
    urgent_damp_ = request;
    have_urgent_damp_ = true;
  } else if (request.kind == ControlRequest::Kind::kHolder) {
    urgent_holder_ = request;
    have_urgent_holder_ = true;
  } else if (urgent_stop_count_ < kUrgentStops) {
    urgent_stops_[urgent_stop_count_++] = request;
  } else {  // a flood of hand-overs within one tick: stop more than was asked, never less
    ControlRequest& last = urgent_stops_[kUrgentStops - 1];
    last = request;
    last.scope = ControlRequest::Scope::kAny;
  }
  return ++last_ticket_;
}

RequestQueue::Taken RequestQueue::Take() {
  std::lock_guard<std::mutex> lock(mutex_);
  Taken taken;
  for (; count_ > 0; --count_, head_ = (head_ + 1) % kSize) taken_queue_[taken.queued++] = queue_[head_];
  taken.stops = std::exchange(urgent_stop_count_, 0);
  std::copy_n(urgent_stops_.begin(), taken.stops, taken_stops_.begin());
  taken.damp = std::exchange(have_urgent_damp_, false);
  taken_damp_ = urgent_damp_;
  taken.holder = std::exchange(have_urgent_holder_, false);
  taken_holder_ = urgent_holder_;
  taken.newest = last_ticket_;
  return taken;
}

}  // namespace flsd
