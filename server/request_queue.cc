#include "server/request_queue.h"

#include <algorithm>
#include <cstring>
#include <utility>

namespace flsd {

uint64_t RequestQueue::Submit(const ControlRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (count_ == kSize) return 0;
  ControlRequest& queued = queue_[(head_ + count_) % kSize];
  queued = request;
  queued.ticket = ++last_ticket_;
  ++count_;
  return last_ticket_;
}

uint64_t RequestQueue::SubmitUrgent(const ControlRequest& request) {
  std::lock_guard<std::mutex> lock(mutex_);
  const uint64_t ticket = ++last_ticket_;
  if (request.kind == ControlRequest::Kind::kDamp) {
    // A third client's press within the tick takes the earlier one's place: its press is as new,
    // so it bars the others' clear_stop as long, and only the newest two pressers differ.
    if (have_urgent_damp_ && std::strcmp(urgent_damp_.client_id.data(), request.client_id.data()) != 0) {
      earlier_damp_ = urgent_damp_;
      have_earlier_damp_ = true;
    }
    urgent_damp_ = request;
    urgent_damp_.ticket = ticket;
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
  return ticket;
}

RequestQueue::Taken RequestQueue::Take() {
  std::lock_guard<std::mutex> lock(mutex_);
  Taken taken;
  for (; count_ > 0; --count_, head_ = (head_ + 1) % kSize) taken_queue_[taken.queued++] = queue_[head_];
  taken.stops = std::exchange(urgent_stop_count_, 0);
  std::copy_n(urgent_stops_.begin(), taken.stops, taken_stops_.begin());
  taken.damp = std::exchange(have_urgent_damp_, false);
  taken_damp_ = urgent_damp_;
  taken.earlier_damp = std::exchange(have_earlier_damp_, false);
  taken_earlier_damp_ = earlier_damp_;
  taken.holder = std::exchange(have_urgent_holder_, false);
  taken_holder_ = urgent_holder_;
  taken.newest = last_ticket_;
  return taken;
}

}  // namespace flsd
