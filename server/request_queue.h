#pragma once
// The requests waiting for the next control tick: a bounded queue, and beside it the urgent ones
// that must never wait behind a full queue or be refused (the emergency stop; stops: a lapsed or
// released lease, the end of a navigation; the lease's new holder). Any thread submits; the
// control thread takes them all once per tick. Each request gets a ticket, counting up, so that
// the request side can tell when a tick has applied it. Nothing here allocates.

#include <array>
#include <cstdint>
#include <mutex>

#include "server/control_request.h"

namespace flsd {

class RequestQueue {
 public:
  static constexpr int kSize = 16;
  static constexpr int kUrgentStops = 8;

  // Returns the request's ticket, or 0 if the queue is full (a flood).
  uint64_t Submit(const ControlRequest& request);
  // Returns the request's ticket. The newest holder is kept, and of the damps the newest and the
  // newest from another client than its (a damp is the stop of its presser, who alone may clear
  // it at once: one presser must not lose that to another's press); stops beyond kUrgentStops
  // merge into one stop of whatever runs.
  uint64_t SubmitUrgent(const ControlRequest& request);

  // Calls apply(request) for every request waiting, in the order they apply: the newest holder,
  // the queue, then the urgent stops in the order they came, then the damps, so that the
  // urgent ones override whatever came with them. No lock is held while `apply` runs. Returns the
  // newest ticket taken: every request with a ticket up to it has now been applied.
  template <class Apply>
  uint64_t TakeAll(Apply&& apply);

 private:
  struct Taken {
    int queued = 0, stops = 0;
    bool damp = false, earlier_damp = false, holder = false;
    uint64_t newest = 0;
  };
  // Moves every waiting request to the taker's copies under one lock, so that none with a ticket
  // up to `newest` stays behind.
  Taken Take();

  std::mutex mutex_;
  std::array<ControlRequest, kSize> queue_{};
  int head_ = 0, count_ = 0;
  ControlRequest urgent_damp_, earlier_damp_;  // the newest; the newest from another client
  bool have_urgent_damp_ = false, have_earlier_damp_ = false;
  ControlRequest urgent_holder_;
  bool have_urgent_holder_ = false;
  std::array<ControlRequest, kUrgentStops> urgent_stops_{};
  int urgent_stop_count_ = 0;
  uint64_t last_ticket_ = 0;
  // The control thread's copies of what it took.
  std::array<ControlRequest, kSize> taken_queue_{};
  ControlRequest taken_damp_, taken_earlier_damp_, taken_holder_;
  std::array<ControlRequest, kUrgentStops> taken_stops_{};
};

template <class Apply>
uint64_t RequestQueue::TakeAll(Apply&& apply) {
  const Taken taken = Take();
  if (taken.holder) apply(taken_holder_);
  for (int i = 0; i < taken.queued; ++i) apply(taken_queue_[i]);
  for (int i = 0; i < taken.stops; ++i) apply(taken_stops_[i]);
  if (taken.earlier_damp) apply(taken_earlier_damp_);
  if (taken.damp) apply(taken_damp_);
  return taken.newest;
}

}  // namespace flsd
