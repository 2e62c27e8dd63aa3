#pragma once
// The requests waiting for the next control tick: a bounded queue, and beside it the urgent ones
// that must never wait behind a full queue or be refused (the emergency stop, and stops: a lapsed
// or released lease, the end of a navigation). Any thread submits; the control thread takes them
// all once per tick. Nothing here allocates.

#include <array>
#include <mutex>

#include "server/control_request.h"

namespace flsd {

class RequestQueue {
 public:
  static constexpr int kSize = 16;
  static constexpr int kUrgentStops = 8;

  // Returns false if the queue is full (a flood).
  bool Submit(const ControlRequest& request);
  // The newest damp is kept; stops beyond kUrgentStops merge into one stop of whatever runs.
  void SubmitUrgent(const ControlRequest& request);

  // Calls apply(request) for every request waiting, in the order they apply: the queue first, then
  // the urgent stops in the order they came, then the newest damp, so that the urgent ones override
  // whatever came with them. No lock is held while `apply` runs.
  template <class Apply>
  void TakeAll(Apply&& apply);

 private:
  bool TakeQueued(ControlRequest& request);
  // Moves the urgent requests to the taker's copies; returns how many stops there are.
  int TakeUrgent(bool& have_damp);

  std::mutex mutex_;
  std::array<ControlRequest, kSize> queue_{};
  int head_ = 0, count_ = 0;
  ControlRequest urgent_damp_;
  bool have_urgent_damp_ = false;
  std::array<ControlRequest, kUrgentStops> urgent_stops_{};
  int urgent_stop_count_ = 0;
  // The control thread's copies of what it took.
  ControlRequest taken_damp_;
  std::array<ControlRequest, kUrgentStops> taken_stops_{};
};

template <class Apply>
void RequestQueue::TakeAll(Apply&& apply) {
  ControlRequest request;
  while (TakeQueued(request)) apply(request);
  bool have_damp = false;
  const int stops = TakeUrgent(have_damp);
  for (int i = 0; i < stops; ++i) apply(taken_stops_[i]);
  if (have_damp) apply(taken_damp_);
}

}  // namespace flsd
