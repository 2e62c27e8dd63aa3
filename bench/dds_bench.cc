#include "bench/dds_bench.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <regex>
#include <string>
#include <thread>

#include "bench/machine.h"
#include "bench/stats.h"
#include "core/check.h"

extern char** environ;

namespace flsd {
namespace {

struct PingResult {
  double p50_us = 0.0, p99_us = 0.0;  // one way, count-weighted over the reporting intervals
  long count = 0;
};

// CYCLONEDDS_URI for this scope, with Cyclone's XML `extra` (if any) after the caller's: how the
// ddsperf children get DDS Security.
class ExtraCycloneConfig {
 public:
  explicit ExtraCycloneConfig(const std::string& extra) {
    const char* old = std::getenv("CYCLONEDDS_URI");
    had_old_ = old != nullptr;
    if (had_old_) old_ = old;
    if (extra.empty()) return;
    setenv("CYCLONEDDS_URI", (old_.empty() ? extra : old_ + "," + extra).c_str(), 1);
  }
  ~ExtraCycloneConfig() {
    if (had_old_) {
      setenv("CYCLONEDDS_URI", old_.c_str(), 1);
    } else {
      unsetenv("CYCLONEDDS_URI");
    }
  }

 private:
  bool had_old_ = false;
  std::string old_;
};

// Runs `ddsperf pong` in the background and `ddsperf ping` for `seconds`, and parses ping's
// interval lines: "... size 12 mean 23.9us min 11.2us 50% 17.9us 90% 37.1us 99% 59.2us max ... cnt 20848".
// `cyclone_xml`: configuration both add to the caller's (empty: none).
PingResult RunDdsperf(int domain_id, double seconds, double rate_hz, const std::string& cyclone_xml) {
  const ExtraCycloneConfig config(cyclone_xml);
  const std::string domain = std::to_string(domain_id);
  const std::string duration = std::to_string(static_cast<int>(std::ceil(seconds)) + 1);
  const char* pong_argv[] = {"ddsperf", "-i", domain.c_str(), "-D", duration.c_str(), "pong", nullptr};
  pid_t pong = 0;
  posix_spawn_file_actions_t quiet;
  posix_spawn_file_actions_init(&quiet);
  posix_spawn_file_actions_addopen(&quiet, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&quiet, 2, "/dev/null", O_WRONLY, 0);
  const int spawned = posix_spawnp(&pong, "ddsperf", &quiet, nullptr, const_cast<char**>(pong_argv), environ);
  posix_spawn_file_actions_destroy(&quiet);
  if (spawned != 0) throw InputError("cannot start ddsperf: is cyclonedds-tools installed?");
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const std::string command = "ddsperf -i " + domain + " -D " + std::to_string(static_cast<int>(std::ceil(seconds))) + " ping " +
                              std::to_string(static_cast<int>(rate_hz)) + "Hz 2>&1";
  FILE* ping = popen(command.c_str(), "r");
  FLSD_DEMAND(ping != nullptr);
  const std::regex line(R"(size \d+ .* 50% ([0-9.]+)us .* 99% ([0-9.]+)us .* cnt (\d+))");
  PingResult result;
  char buffer[1024];
  double sum50 = 0.0, sum99 = 0.0;
  while (std::fgets(buffer, sizeof buffer, ping) != nullptr) {
    std::cmatch m;
    if (!std::regex_search(buffer, m, line)) continue;
    const long n = std::stol(m[3]);
    sum50 += std::stod(m[1]) * n;
    sum99 += std::stod(m[2]) * n;
    result.count += n;
  }
  pclose(ping);
  kill(pong, SIGTERM);
  waitpid(pong, nullptr, 0);
  if (result.count == 0) throw InputError("ddsperf ping reported no round trips (is the domain reachable?)");
  result.p50_us = sum50 / result.count;
  result.p99_us = sum99 / result.count;
  return result;
}

}  // namespace

nlohmann::json RunDdsBenchmark(Client& client, int domain_id, const DdsBenchOptions& options) {
  using Clock = std::chrono::steady_clock;
  std::vector<double> rtt_us;
  rtt_us.reserve(options.calls);
  int unanswered = 0;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / options.rate_hz));
  auto next = Clock::now();
  for (int i = -100; i < options.calls; ++i) {
    std::this_thread::sleep_until(next);
    next += period;
    const auto start = Clock::now();
    const Reply r = client.Status(std::chrono::milliseconds(1000));
    const double us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    if (!r.answered()) ++unanswered;
    if (i >= 0 && r.answered()) rtt_us.push_back(us);
  }
  const PingResult ping = RunDdsperf(domain_id, options.ddsperf_seconds, options.rate_hz, dds::SecurityXml(options.security));
  const double p50 = Quantile(rtt_us, 0.5), p99 = Quantile(rtt_us, 0.99);
  const double ddsperf_rtt_p50 = 2.0 * ping.p50_us;
  nlohmann::json result = {
      {"benchmark", "skillctl bench"},
      {"calls", options.calls},
      {"rate_hz", options.rate_hz},
      {"unanswered", unanswered},
      {"rtt_min_us", Quantile(rtt_us, 0.0)},
      {"rtt_p50_us", p50},
      {"rtt_p99_us", p99},
      {"ddsperf_rtt_p50_us", ddsperf_rtt_p50},
      {"ddsperf_rtt_p99_us", 2.0 * ping.p99_us},
      {"ddsperf_round_trips", ping.count},
      {"ratio", p50 / ddsperf_rtt_p50},
      {"target_ratio_at_most", 1.5},
      {"machine", MachineDescription()},
      {"dds_security", options.security.enabled},
  };
  if (options.security.enabled) {  // what authentication and encryption add to a DDS round trip
    const PingResult plain = RunDdsperf(domain_id, options.ddsperf_seconds, options.rate_hz, "");
    result["ddsperf_unsecured_rtt_p50_us"] = 2.0 * plain.p50_us;
    result["ddsperf_unsecured_rtt_p99_us"] = 2.0 * plain.p99_us;
    result["security_cost_p50_us"] = ddsperf_rtt_p50 - 2.0 * plain.p50_us;
  }
  return result;
}

}  // namespace flsd
