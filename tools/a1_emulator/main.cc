// a1_emulator: plays the Unitree A1's side of the low-level UDP protocol on this machine, backed
// by the MuJoCo A1, so that `skilld --backend hw` can be run and tested without a robot.

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>


#include "core/check.h"
#include "core/signals.h"
#include "emulator/a1_emulator.h"

int main(int argc, char** argv) {
  CLI::App app{"a1_emulator: a simulated A1 behind the low-level UDP protocol"};
  flsd::hw::EmulatorConfig config;
  flsd::hw::EmulatorFaults faults;
  app.add_option("--host", config.host, "Address to listen on");
  app.add_option("--port", config.port, "UDP port (the A1's is 8007)")->check(CLI::Range(0, 65535));
  app.add_option("--drop", faults.drop_fraction, "Fraction of state frames dropped")->check(CLI::Range(0.0, 1.0));
  app.add_option("--corrupt", faults.corrupt_fraction, "Fraction of state frames with a broken CRC")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--late-ms", faults.late_ms, "Delay of every state frame")->check(CLI::Range(0.0, 10000.0));
  bool frozen = false;
  app.add_flag("--frozen", frozen, "IMU and joint readings stop changing");
  app.add_flag("--frozen-imu", faults.frozen_imu, "IMU readings stop changing");
  app.add_flag("--frozen-joints", faults.frozen_joints, "Joint encoder readings stop changing");
  app.add_option("--dead-motor", faults.dead_motor, "Joint whose motor gives no torque")->check(CLI::Range(-1, 11));
  double fault_after = 0.0;
  app.add_option("--faults-after", fault_after, "Seconds of healthy running before the faults begin")
      ->check(CLI::Range(0.0, 1e6));
  CLI11_PARSE(app, argc, argv);
  faults.frozen_imu |= frozen;
  faults.frozen_joints |= frozen;

  flsd::BlockTerminationSignals();
  try {
    flsd::hw::A1Emulator emulator(config);
    emulator.Start();
    spdlog::info("a1_emulator listening on {}:{}", config.host, emulator.port());
    const bool stopped_early = fault_after > 0.0 && flsd::WaitForTermination(fault_after) != 0;
    if (!stopped_early) {
      emulator.SetFaults(faults);
      flsd::WaitForTermination();
    }
    emulator.Stop();
    const flsd::hw::EmulatorStats s = emulator.stats();
    spdlog::info("a1_emulator stopped: {} commands, {} bad, {} states sent", s.commands, s.bad_commands, s.states_sent);
    return 0;
  } catch (const flsd::InputError& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
}
