#include "bench/hw_bench.h"

#include <chrono>
#include <thread>

#include "bench/machine.h"
#include "emulator/a1_emulator.h"
#include "hw/hw_backend.h"
#include "server/control_loop.h"
#include "server/server_config.h"

namespace flsd {

nlohmann::json RunHwBenchmark(const HwBenchOptions& options) {
  const ServerConfig defaults;
  const CpuLatencyRequest cpu_latency(defaults.cpu_latency_us);
  hw::EmulatorConfig emulator_config;
  emulator_config.port = 0;
  hw::A1Emulator emulator(emulator_config);
  emulator.Start();
  hw::HwConfig config = defaults.hw;
  config.local_host = config.robot_host = "127.0.0.1";
  config.local_port = 0;
  config.robot_port = emulator.port();
  hw::HwBackend backend(config);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // warm up
  const hw::DriverStats before = backend.stats();
  const auto start = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(options.seconds));
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const hw::DriverStats after = backend.stats();
  emulator.Stop();
  const double sent = static_cast<double>(after.sent - before.sent);
  return {{"benchmark", "flsd bench hw"},
          {"seconds", elapsed},
          {"sched_fifo", backend.realtime()},
          {"cpu_dma_latency_held", cpu_latency.active()},
          {"send_rate_hz", sent / elapsed},
          {"target_rate_hz", config.rate_hz},
          {"send_jitter_p50_ms", backend.send_lateness().Quantile(0.5) * 1e3},
          {"send_jitter_p99_ms", backend.send_lateness().Quantile(0.99) * 1e3},
          {"target_jitter_p99_ms_below", 0.5},
          {"round_trip_p50_ms", backend.round_trip().Quantile(0.5) * 1e3},
          {"round_trip_p99_ms", backend.round_trip().Quantile(0.99) * 1e3},
          {"late_cycles", after.late_cycles - before.late_cycles},
          {"states_received", after.received - before.received},
          {"states_malformed", (after.bad_crc - before.bad_crc) + (after.bad_length - before.bad_length)},
          {"machine", MachineDescription()}};
}

}  // namespace flsd
