#pragma once
// Runs Controller::Tick at the control rate on its own thread, paced by the monotonic clock.
// A tick that starts more than half a period late is a deadline miss; after a stall the loop
// resumes from now instead of catching up with a burst of ticks.

#include <atomic>
#include <cstdint>
#include <thread>

#include "server/controller.h"

namespace flsd {

class ControlLoop {
 public:
  explicit ControlLoop(Controller& controller) : controller_(controller) {}
  ~ControlLoop() { Stop(); }

  void Start();
  // Finishes the current tick and returns; the backend keeps the last command (the caller damps).
  void Stop();

  uint64_t deadline_misses() const { return deadline_misses_.load(std::memory_order_relaxed); }
  // The worst lateness of a tick start seen so far, s.
  double worst_lateness() const { return worst_lateness_.load(std::memory_order_relaxed); }

 private:
  void Run();

  Controller& controller_;
  std::thread thread_;
  std::atomic<bool> running_{false};
  std::atomic<uint64_t> deadline_misses_{0};
  std::atomic<double> worst_lateness_{0.0};
};

}  // namespace flsd
