#pragma once
// Runs Controller::Tick at the control rate on its own thread, paced by the monotonic clock.
// A tick that starts more than half a period late is a deadline miss; after a stall the loop
// resumes from now instead of catching up with a burst of ticks.

#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>

#include "core/latency_histogram.h"
#include "server/controller.h"

namespace flsd {

// Asks the kernel, through /dev/cpu_dma_latency, to keep the CPUs out of idle states slower to
// leave than `microseconds`, for as long as the object lives (the practice of cyclictest and
// real-time robot computers). 0 makes idle CPUs poll: wake-ups get sharp, power use goes up.
class CpuLatencyRequest {
 public:
  explicit CpuLatencyRequest(int microseconds);
  ~CpuLatencyRequest();
  CpuLatencyRequest(const CpuLatencyRequest&) = delete;
  CpuLatencyRequest& operator=(const CpuLatencyRequest&) = delete;
  bool active() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

class ControlLoop {
 public:
  // `priority` > 0 asks for SCHED_FIFO at that priority (it needs CAP_SYS_NICE or root); the loop
  // runs anyway without it, and realtime() says which it got.
  // `cpu_latency_us` >= 0 holds a CpuLatencyRequest while the loop runs; -1 leaves the CPUs be.
  ControlLoop(Controller& controller, int priority = 0, int cpu_latency_us = -1)
      : controller_(controller), priority_(priority), cpu_latency_us_(cpu_latency_us) {}
  ~ControlLoop() { Stop(); }

  void Start();
  // Finishes the current tick and returns; the backend keeps the last command (the caller damps).
  void Stop();

  uint64_t deadline_misses() const { return deadline_misses_.load(std::memory_order_relaxed); }
  // The worst lateness of a tick start seen so far, s.
  double worst_lateness() const { return worst_lateness_.load(std::memory_order_relaxed); }
  // The q-quantile of tick-start lateness (the loop's jitter), s, to 10 us.
  double LatenessQuantile(double q) const { return lateness_.Quantile(q); }
  uint64_t ticks() const { return lateness_.count(); }
  bool realtime() const { return realtime_; }
  bool cpu_latency_held() const { return cpu_latency_ != nullptr && cpu_latency_->active(); }

 private:
  void Run();

  Controller& controller_;
  int priority_;
  int cpu_latency_us_;
  bool realtime_ = false;
  std::unique_ptr<CpuLatencyRequest> cpu_latency_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<uint64_t> deadline_misses_{0};
  std::atomic<double> worst_lateness_{0.0};
  LatencyHistogram lateness_;  // of tick starts
};

}  // namespace flsd
