// skillctl: command-line client of skilld. Exit codes: 0 done, 1 refused by the server,
// 2 no server answering, 4 a motion that ended without success (safety stop, lease lost...).

#include <CLI/CLI.hpp>

#include <array>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "bench/dds_bench.h"
#include "bench/request_echo.h"
#include "client/client.h"
#include "client/navigation_picture.h"
#include "comm/protocol.h"

namespace {

constexpr int kExitRefused = 1;
constexpr int kExitNoServer = 2;
constexpr int kExitTaskFailed = 4;

std::atomic<bool> g_interrupted{false};
void OnSignal(int) { g_interrupted = true; }

void PrintState(const flsd::StateReport& s) {
  std::printf("t %7.2f  %-8s", s.time, flsd::Name(s.mode));
  // In stand, a skill is the one braking the last motion.
  if (s.skill < 0) {
    std::printf("     ");
  } else {
    std::printf(s.mode == flsd::Mode::kStand ? " b%-3d" : " %-4d", s.skill);
  }
  std::printf("  xyz %6.2f %6.2f %5.2f  v %5.2f %5.2f  wz %5.2f", s.position[0], s.position[1], s.position[2],
              s.linear_velocity[0], s.linear_velocity[1], s.angular_velocity[2]);
  if (s.faults != 0) std::printf("  FAULT %s", s.fault_message.c_str());
  std::printf("\n");
  std::fflush(stdout);
}

// What the robot did while the motion ran: where it went, how fast, and whether it fell.
struct MotionSummary {
  bool started = false;
  double t0 = 0.0, x0 = 0.0, y0 = 0.0, turned = 0.0, last_yaw = 0.0;
  double t1 = 0.0, x1 = 0.0, y1 = 0.0;

  void Add(const flsd::StateReport& s) {
    const bool moving = s.mode == flsd::Mode::kSkill || s.mode == flsd::Mode::kVelocity || s.mode == flsd::Mode::kNavigate;
    if (!moving) return;
    const double yaw = s.yaw();
    if (!started) {
      started = true;
      t0 = s.time, x0 = s.position[0], y0 = s.position[1], last_yaw = yaw;
    }
    turned += std::remainder(yaw - last_yaw, 2.0 * M_PI);  // unwrapped
    last_yaw = yaw;
    t1 = s.time, x1 = s.position[0], y1 = s.position[1];
  }
  void Print(bool fell, const std::string& why) const {
    const double t = t1 - t0, d = std::hypot(x1 - x0, y1 - y0);
    std::printf("moved %.2f m (dx %+.2f, dy %+.2f) in %.2f s: %.2f m/s; turned %+.0f deg; fell: %s\n", d, x1 - x0,
                y1 - y0, t, t > 0.0 ? d / t : 0.0, turned * 180.0 / M_PI, fell ? ("yes, " + why).c_str() : "no");
  }
};

// Follows this client's long call until it ends; Ctrl-C stops the robot.
// With `record`, keeps what a navigation planned and where the robot walked.
int FollowTask(flsd::Client& client, const char* call, const flsd::Task& task, bool quiet,
               flsd::NavigationRecord* record = nullptr) {
  const auto start = std::chrono::steady_clock::now();
  auto last_print = start - std::chrono::seconds(1);
  MotionSummary summary;
  uint64_t last_tick = 0;
  for (;;) {
    if (g_interrupted) {
      std::printf("interrupted: stopping\n");
      (void)client.Stop();
      return kExitTaskFailed;
    }
    // Each sample once: the latest again would count twice.
    const std::optional<flsd::StateReport> s = client.NextState(last_tick, std::chrono::milliseconds(1000));
    if (!s) {
      std::fprintf(stderr, "skillctl: no state from skilld for 1 s\n");
      return kExitNoServer;
    }
    last_tick = s->tick;
    summary.Add(*s);
    const flsd::TaskReport progress = task.Progress();
    const bool ours = s->task.client_id == client.id() && s->task.request_id == task.request_id();
    if (record != nullptr && ours) {
      if (!s->task.path.empty() && (record->planned.empty() || record->planned.back() != s->task.path)) {
        record->planned.push_back(s->task.path);
      }
      if (s->mode == flsd::Mode::kNavigate) {
        record->walked_x.push_back(s->position[0]);
        record->walked_y.push_back(s->position[1]);
      }
    }
    const auto now = std::chrono::steady_clock::now();
    if (progress.state == flsd::TaskState::kNone && now - start > std::chrono::seconds(3)) {
      std::fprintf(stderr, "skillctl: the server accepted %s but never reported it on the state topic\n", call);
      return kExitTaskFailed;
    }
    if (!quiet && now - last_print >= std::chrono::milliseconds(500)) {
      PrintState(*s);
      last_print = now;
    }
    if (progress.ended()) {
      if (!quiet) PrintState(*s);
      const std::string outcome = std::string(call) + " " + flsd::Name(progress.state) + ": " + progress.message;
      std::printf("%s\n", outcome.c_str());
      if (record != nullptr) record->outcome = outcome;
      summary.Print(progress.state == flsd::TaskState::kSafetyStop, progress.message);
      return progress.state == flsd::TaskState::kSucceeded ? 0 : kExitTaskFailed;
    }
    if (client.lost_control()) {
      std::printf("%s: control was lost\n", call);
      return kExitTaskFailed;
    }
  }
}

// Holds control until the robot stands, or `timeout` passes.
void WaitForStand(const flsd::Client& client, std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  uint64_t tick = 0;
  while (std::chrono::steady_clock::now() < until) {
    const std::optional<flsd::StateReport> s = client.NextState(tick, std::chrono::milliseconds(200));
    if (!s) continue;
    if (s->mode == flsd::Mode::kStand) return;
    tick = s->tick;
  }
}

int Report(const flsd::Reply& r) {
  if (!r.answered()) {
    std::fprintf(stderr, "skillctl: %s\n", r.Describe().c_str());
    return kExitNoServer;
  }
  std::printf("%s\n", r.Describe().c_str());
  return r.ok() ? 0 : kExitRefused;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"skillctl: talk to skilld, the FLSD skill server"};
  app.require_subcommand(1);
  flsd::Client::Options options;
  double timeout_s = 3.0;
  bool quiet = false;
  app.add_option("--domain", options.domain_id, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--partition", options.partition, "DDS partition");
  app.add_option("--timeout", timeout_s, "Seconds to wait for the server")->check(CLI::Range(0.1, 600.0));
  app.add_flag("--quiet", quiet, "Print only the outcome of a motion");
  app.add_option("--id", options.client_id,
                 "Client id (default: host-pid-random; with --security, this participant's identity, and no other); "
                 "give damp and clear the same one to clear at once")
      ->check([](const std::string& id) { return id.size() < 64 ? std::string() : std::string("at most 63 characters"); });
  std::string security_file;
  app.add_option("--security", security_file,
                 "DDS Security: a YAML file with a security: section (scripts/make_pki.sh writes one per identity); "
                 "the client id is then this identity's")
      ->envname("FLSD_SECURITY");

  int skill_id = 0;
  double duration = 0.0;
  std::array<double, 3> velocity{};
  std::array<double, 2> goal{};
  double watch_seconds = 0.0;
  std::string map_file;
  app.add_subcommand("list", "List the library's skills");
  app.add_subcommand("status", "Print the server's mode, control holder and faults");
  CLI::App* skill = app.add_subcommand("skill", "Run skill K for --duration seconds, then stand");
  skill->add_option("k", skill_id, "Skill id")->required();
  skill->add_option("--duration", duration, "Seconds")->required();
  CLI::App* vel = app.add_subcommand("vel", "Track a body velocity for --duration seconds");
  vel->add_option("vx", velocity[0], "m/s")->required();
  vel->add_option("vy", velocity[1], "m/s")->required();
  vel->add_option("wz", velocity[2], "rad/s")->required();
  vel->add_option("--duration", duration, "Seconds")->required();
  CLI::App* go = app.add_subcommand("goto", "Walk to (X, Y) around the map's obstacles");
  go->add_option("x", goal[0], "m")->required();
  go->add_option("y", goal[1], "m")->required();
  go->add_option("--map", map_file, "Map (YAML); default: the server's");
  go->add_option("--duration", duration, "Give up after this many seconds (default: the server's timeout)");
  std::string picture;
  go->add_option("--picture", picture, "Write the planned and walked paths to this SVG");
  app.add_subcommand("stop", "End the current motion; the robot stands");
  app.add_subcommand("stand", "Stand in the default pose (clears a safety stop once upright)");
  app.add_subcommand("damp", "Emergency stop: damp all joints (any client may); it latches until cleared");
  app.add_subcommand("clear", "Clear an emergency stop (whoever pressed it, or anyone after the hold time); then stand");
  app.add_subcommand("reset", "Put the simulated robot back on its feet");
  CLI::App* watch = app.add_subcommand("watch", "Print the robot's state as it changes");
  watch->add_option("--seconds", watch_seconds, "Stop after this long (0: until Ctrl-C)");
  flsd::DdsBenchOptions bench_options;
  CLI::App* bench = app.add_subcommand(
      "bench", "Round trips to skilld against a bare DDS echo of the same calls and Cyclone's ddsperf; prints JSON");
  bench->add_option("--rate", bench_options.rate_hz, "Calls (and pings) per second")->check(CLI::Range(1.0, 100000.0));
  bench->add_option("--blocks", bench_options.blocks, "Pairs of blocks: skilld's calls, then ddsperf's pings")
      ->check(CLI::Range(1, 1000));
  bench->add_option("--block-seconds", bench_options.block_seconds, "Length of each block")->check(CLI::Range(1, 600));
  bool json = false;  // JSON is the only output; the flag is accepted for symmetry with flsd bench
  bench->add_flag("--json", json, "Print one JSON object (the default output)");
  // bench's echo (bench/request_echo.h), started by bench itself in a process of its own.
  long echo_seconds = 60;
  CLI::App* echo = app.add_subcommand("bench-echo", "")->group("");  // hidden
  echo->add_option("--seconds", echo_seconds, "Answer calls for this long")->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  const std::string command = app.get_subcommands().front()->get_name();
  if (command == "bench-echo") {
    try {
      const flsd::RequestEcho echo_peer(options.domain_id, options.partition);
      const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(echo_seconds);
      while (!g_interrupted && std::chrono::steady_clock::now() < until) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      return 0;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "skillctl bench-echo: %s\n", e.what());
      return kExitRefused;
    }
  }
  const auto timeout = std::chrono::milliseconds(static_cast<int>(timeout_s * 1000));
  try {
    std::string map_yaml;
    if (!map_file.empty()) {
      std::ifstream in(map_file);
      if (!in) {
        std::fprintf(stderr, "skillctl: cannot read map %s\n", map_file.c_str());
        return kExitRefused;
      }
      std::stringstream text;
      text << in.rdbuf();
      map_yaml = text.str();
    }
    if (!security_file.empty()) {
      options.security = flsd::dds::LoadSecurityFile(security_file);
      bench_options.security = options.security;
    }
    bench_options.partition = options.partition;
    flsd::Client client(options);
    if (!client.WaitForServer(timeout)) {
      // With DDS Security, a server and a client that do not share a CA simply never meet.
      std::fprintf(stderr, "skillctl: no skilld answers on DDS domain %d, partition '%s' (waited %.1f s)%s\n",
                   options.domain_id, options.partition.c_str(), timeout_s,
                   options.security.enabled ? "; is it a server of this deployment (the same CA)?"
                                            : "; a server with DDS Security answers only with --security");
      return kExitNoServer;
    }
    if (command == "list") {
      const std::vector<flsd::SkillInfo> skills = client.ListSkills();
      std::printf("%-5s %8s %8s %8s %8s %8s %9s\n", "skill", "vx m/s", "vy m/s", "wz rad/s", "height m", "gait Hz",
                  "survival");
      for (const flsd::SkillInfo& s : skills) {
        std::printf("%-5d %8.2f %8.2f %8.2f %8.3f %8.2f %9d\n", s.id, s.linear_velocity[0], s.linear_velocity[1],
                    s.angular_velocity[2], s.base_height, s.gait_frequency, s.survival_steps);
      }
      return 0;
    }
    if (command == "status") return Report(client.Status());
    if (command == "damp") return Report(client.Damp());
    if (command == "clear") return Report(client.ClearStop());
    if (command == "bench") {
      std::printf("%s\n", flsd::RunDdsBenchmark(client, options.domain_id, bench_options).dump(2).c_str());
      return 0;
    }
    if (command == "watch") {
      const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<int>(watch_seconds * 1000));
      while (!g_interrupted && (watch_seconds <= 0.0 || std::chrono::steady_clock::now() < until)) {
        const std::optional<flsd::StateReport> s = client.NextState(0, std::chrono::milliseconds(1000));
        if (!s) {
          std::fprintf(stderr, "skillctl: no state from skilld for 1 s\n");
          return kExitNoServer;
        }
        PrintState(*s);
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
      }
      return 0;
    }

    // Motion: take control for the length of the command.
    const flsd::Reply acquired = client.AcquireControl(timeout);
    if (!acquired.ok()) return Report(acquired);
    int code = 0;
    if (command == "skill" || command == "vel" || command == "goto") {
      const flsd::Task task = command == "skill" ? client.ExecuteSkill(skill_id, duration, timeout)
                              : command == "vel" ? client.TrackVelocity(velocity[0], velocity[1], velocity[2], duration, timeout)
                                                 : client.Navigate(goal[0], goal[1], map_yaml, duration, timeout);
      const char* call = flsd::CallName(command == "skill" ? flsd::Call::kExecuteSkill
                                             : command == "vel" ? flsd::Call::kTrackVelocity
                                                                : flsd::Call::kNavigate);
      code = Report(task.reply());
      if (code == 0) {
        flsd::NavigationRecord record;
        record.goal_x = goal[0];
        record.goal_y = goal[1];
        code = FollowTask(client, call, task, quiet, picture.empty() ? nullptr : &record);
        if (!picture.empty()) {
          std::optional<flsd::Map2D> map;
          if (!map_yaml.empty()) map = flsd::Map2D::Parse(map_yaml, map_file);
          flsd::WriteNavigationPicture(picture, map, record);
          std::printf("picture: %s\n", picture.c_str());
        }
      }
    } else if (command == "stand") {
      code = Report(client.Stand(timeout));
      if (code == 0) {
        WaitForStand(client, timeout);
        std::this_thread::sleep_for(std::chrono::seconds(1));  // hold control while it rises
      }
    } else {
      code = Report(command == "stop" ? client.Stop(timeout) : client.Reset(timeout));
    }
    client.ReleaseControl(timeout);
    return code;
  } catch (const flsd::CallError& e) {
    return Report(e.reply());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "skillctl: %s\n", e.what());
    return kExitNoServer;
  }
}
