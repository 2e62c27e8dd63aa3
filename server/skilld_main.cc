// skilld: the skill server. Hosts a skill library, drives a backend at 50 Hz, answers DDS
// requests, and publishes the robot's state, until SIGINT or SIGTERM.

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <memory>
#include <thread>

#include "core/check.h"
#include "core/paths.h"
#include "core/signals.h"
#include "hw/hw_backend.h"
#include "server/control_loop.h"
#include "server/dds_service.h"
#include "sim/sim_backend.h"

namespace {

constexpr int kExitBadInput = 2;

// Cyclone's receive thread takes buffers of about 1 MB and frees them later. glibc raises its mmap
// threshold to the size of the first such block freed, so the later ones came from the thread's
// arena, whose pages stay resident: skilld's RSS rose in steps of 1-2 MB under load. With the
// threshold fixed, a block that large has its own mapping and goes back to the system when freed.
constexpr int kMmapThresholdBytes = 256 * 1024;
// What the arenas hold free is handed back this often, from the main thread: the control loop
// allocates nothing while the robot is healthy, so it never waits on an arena's lock for it.
constexpr double kTrimPeriodSeconds = 60.0;

// Waits for SIGINT or SIGTERM, or for `run_seconds` if positive; returns the signal, or 0.
int ServeUntilSignalled(double run_seconds) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                   std::chrono::duration<double>(run_seconds));
  for (;;) {
    double wait = kTrimPeriodSeconds;
    if (run_seconds > 0.0) {
      const double left = std::chrono::duration<double>(end - Clock::now()).count();
      if (left <= 0.0) return 0;
      wait = std::min(wait, left);
    }
    if (const int signal = flsd::WaitForTermination(wait); signal > 0) return signal;
    malloc_trim(0);
  }
}

std::unique_ptr<flsd::Backend> MakeBackend(const std::string& name, const flsd::ServerConfig& config) {
  if (name == "sim") return std::make_unique<flsd::SimBackend>(config.sim);
  auto hw = std::make_unique<flsd::hw::HwBackend>(config.hw);
  spdlog::info("pre-flight: talking to the A1 at {}:{} without torque for {:.1f} s", config.hw.robot_host,
               config.hw.robot_port, config.hw.preflight_seconds);
  const std::vector<std::string> failures = hw->Preflight();
  if (!failures.empty()) {
    for (const std::string& f : failures) spdlog::error("pre-flight: {}", f);
    throw flsd::InputError("pre-flight failed: " + std::to_string(failures.size()) + " problem(s); torque stays off");
  }
  spdlog::info("pre-flight passed");
  return hw;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"skilld: the FLSD skill server for the Unitree A1"};
  std::string backend_name = "sim", library_path, config_path = "configs/server.yaml", partition;
  int domain_id = -1;
  double run_seconds = 0.0;
  app.add_option("--backend", backend_name, "sim (MuJoCo) or hw (the real A1)")->check(CLI::IsMember({"sim", "hw"}));
  app.add_option("--library", library_path, "Skill library (.safetensors)")->required();
  app.add_option("--config", config_path, "Server config (YAML)");
  app.add_option("--domain", domain_id, "DDS domain id (default: the config's)")->check(CLI::Range(0, 232));
  app.add_option("--partition", partition, "DDS partition (default: the config's)");
  app.add_option("--run-seconds", run_seconds, "Stop by itself after this long (0: run until signalled)")
      ->check(CLI::Range(0.0, 1e9));
  CLI11_PARSE(app, argc, argv);

  flsd::BlockTerminationSignals();
  mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes);

  try {
    flsd::ServerConfig config = flsd::LoadServerConfig(flsd::ResolveDataPath(config_path));
    if (domain_id >= 0) config.domain_id = domain_id;
    if (!partition.empty()) config.partition = partition;
    const flsd::SkillLibrary library = flsd::SkillLibrary::Load(library_path);
    std::unique_ptr<flsd::Backend> backend = MakeBackend(backend_name, config);

    flsd::Controller controller(*backend, library, config);
    flsd::ControlLoop loop(controller, config.control_priority, config.cpu_latency_us);
    flsd::DdsService service(config, controller, loop, backend->name());
    loop.Start();
    service.Start();
    if (!controller.has_brake_skill()) {
      spdlog::warn("library {} has no dependable skill within {} m/s of standing still: a motion ends in the stand "
                   "unbraked, which can throw a walking robot",
                   library.path(), flsd::Controller::kStillSpeed);
    }
    if (config.control_priority > 0 && !loop.realtime()) {
      spdlog::warn("control loop runs without SCHED_FIFO (needs CAP_SYS_NICE): expect more jitter");
    }
    if (config.cpu_latency_us >= 0 && !loop.cpu_latency_held()) {
      spdlog::warn("cannot hold /dev/cpu_dma_latency (needs root): expect millisecond wake-ups on idle CPUs");
    }
    spdlog::info("skilld ready: backend {}, library {} ({} skills), DDS domain {}, partition '{}'", backend->name(),
                 library.path(), library.num_skills(), config.domain_id, config.partition);

    const int signal = ServeUntilSignalled(run_seconds);
    spdlog::info("skilld stopping ({}): damping the robot", signal > 0 ? strsignal(signal) : "run time over");
    service.Stop();
    flsd::ControlRequest damp;
    damp.kind = flsd::ControlRequest::Kind::kDamp;
    flsd::SetText(damp.reason, "server shutting down");
    controller.SubmitUrgent(damp);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // a few ticks of damping
    loop.Stop();
    spdlog::info("skilld stopped after {} ticks, {} deadline misses, {} replies; tick lateness p50 {:.2f} ms, "
                 "p99 {:.2f} ms, worst {:.2f} ms", controller.status().tick, loop.deadline_misses(),
                 service.replies_sent(), loop.LatenessQuantile(0.5) * 1e3, loop.LatenessQuantile(0.99) * 1e3,
                 loop.worst_lateness() * 1e3);
    return 0;
  } catch (const flsd::InputError& e) {
    spdlog::error("{}", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    spdlog::error("skilld failed: {}", e.what());
    return 1;
  }
}
