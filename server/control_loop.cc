#include "server/control_loop.h"

#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>
#include <sched.h>
#include <sys/prctl.h>
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

CpuLatencyRequest::CpuLatencyRequest(int microseconds) {
  fd_ = open("/dev/cpu_dma_latency", O_WRONLY | O_CLOEXEC);
  const int32_t value = microseconds;
  if (fd_ >= 0 && write(fd_, &value, sizeof value) != sizeof value) {
    close(fd_);
    fd_ = -1;
  }
}

CpuLatencyRequest::~CpuLatencyRequest() {
  if (fd_ >= 0) close(fd_);  // closing withdraws the request
}

void ControlLoop::Start() {
  if (cpu_latency_us_ >= 0) cpu_latency_ = std::make_unique<CpuLatencyRequest>(cpu_latency_us_);
  running_ = true;
  thread_ = std::thread([this] {
    prctl(PR_SET_TIMERSLACK, 1UL);  // wake within 1 ns of the deadline, not the default 50 us
    Run();
  });
  if (priority_ > 0) {
    sched_param param{};
    param.sched_priority = priority_;
    realtime_ = pthread_setschedparam(thread_.native_handle(), SCHED_FIFO, &param) == 0;
  }
}

void ControlLoop::Stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
  cpu_latency_.reset();
}

void ControlLoop::Run() {
  const int64_t period = static_cast<int64_t>(a1::kControlDt * kNsPerS);
  int64_t next = MonotonicNs();
  while (running_.load(std::memory_order_relaxed)) {
    const int64_t late = MonotonicNs() - next;
    if (late > period / 2) deadline_misses_.fetch_add(1, std::memory_order_relaxed);
    if (late * 1e-9 > worst_lateness_.load(std::memory_order_relaxed)) worst_lateness_.store(late * 1e-9);
    lateness_.Add(late * 1e-9);
    if (late > period) next = MonotonicNs();  // a stall: resume from now, no burst of ticks
    controller_.Tick();
    next += period;
    SleepUntil(next);
  }
}

}  // namespace flsd
