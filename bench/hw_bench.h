#pragma once
#include <nlohmann/json.hpp>

namespace flsd {

struct HwBenchOptions {
  double seconds = 10.0;  // 5000 driver cycles at 500 Hz
};

// HwBackend's 500 Hz driver against the robot emulator on loopback, with skilld's real-time
// settings (SCHED_FIFO, /dev/cpu_dma_latency): achieved send rate, send jitter against the 2 ms
// schedule and command-to-state round trip (p50, p99, over the whole run, 0.5 s of warm-up
// included), late cycles, and frames lost.
nlohmann::json RunHwBenchmark(const HwBenchOptions& options);

}  // namespace flsd
