#include "server/control_loop.h"

#include <time.h>

namespace flsd {
namespace {

constexpr int64_t kNsPerS = 1000000000;

int64_t MonotonicNs() {
  timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec * kNsPerS + t.tv_nsec;
}

void SleepUntil(int64_t ns) {
  const timespec t{static_cast<time_t>(ns / kNsPerS), static_cast<long>(ns % kNsPerS)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, nullptr) != 0) {
  }
}

}  // namespace

void ControlLoop::Start() {
  running_ = true;
  thread_ = std::thread([this] { Run(); });
}

void ControlLoop::Stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

void ControlLoop::Run() {
  const int64_t period = static_cast<int64_t>(a1::kControlDt * kNsPerS);
  int64_t next = MonotonicNs();
  while (running_.load(std::memory_order_relaxed)) {
    const int64_t late = MonotonicNs() - next;
    if (late > period / 2) deadline_misses_.fetch_add(1, std::memory_order_relaxed);
    if (late * 1e-9 > worst_lateness_.load(std::memory_order_relaxed)) worst_lateness_.store(late * 1e-9);
    if (late > period) next = MonotonicNs();  // a stall: resume from now, no burst of ticks
    controller_.Tick();
    next += period;
    SleepUntil(next);
  }
}

}  // namespace flsd
