#include "bench/dds_bench.h"

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "bench/child_process.h"
#include "bench/machine.h"
#include "bench/request_echo.h"
#include "bench/stats.h"
#include "core/check.h"
#include "core/paths.h"

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

// `ddsperf pong` in the background for `seconds` or as long as this object lives, whichever is shorter.
class DdsperfPong {
 public:
  DdsperfPong(int domain_id, int seconds) : pong_(Start(domain_id, seconds)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
  ~DdsperfPong() { pong_->Stop(SIGTERM, std::chrono::seconds(2)); }
  DdsperfPong(const DdsperfPong&) = delete;
  DdsperfPong& operator=(const DdsperfPong&) = delete;

 private:
  static std::unique_ptr<ChildProcess> Start(int domain_id, int seconds) {
    try {
      return std::make_unique<ChildProcess>(
          std::vector<std::string>{"ddsperf", "-i", std::to_string(domain_id), "-D", std::to_string(seconds), "pong"},
          "/dev/null");
    } catch (const InputError&) {
      throw InputError("cannot start ddsperf: is cyclonedds-tools installed?");
    }
  }

  std::unique_ptr<ChildProcess> pong_;
};

// Runs `ddsperf ping` for `seconds` against a pong, and parses its interval lines:
// "... size 12 mean 23.9us min 11.2us 50% 17.9us 90% 37.1us 99% 59.2us max ... cnt 20848".
PingResult Ping(int domain_id, int seconds, double rate_hz) {
  const std::string command = "ddsperf -i " + std::to_string(domain_id) + " -D " + std::to_string(seconds) + " ping " +
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
  if (result.count == 0) throw InputError("ddsperf ping reported no round trips (is the domain reachable?)");
  result.p50_us = sum50 / result.count;
  result.p99_us = sum99 / result.count;
  return result;
}

// Status round trips, `calls` of them at `rate_hz`, to skilld and, when `echo` is given, to the
// echo right beside each one (in turn first and second, so that neither always follows the
// other); those unanswered are counted, not timed.
struct RoundTrips {
  std::vector<double> us;
  int unanswered = 0;
  void Time(Client& client) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    const Reply r = client.Status(std::chrono::milliseconds(1000));
    if (!r.answered()) {
      ++unanswered;
      return;
    }
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
  }
};
struct Block {
  RoundTrips skilld, echo;
};
Block StatusRoundTrips(Client& skilld, Client* echo, int calls, double rate_hz) {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate_hz));
  constexpr int kEchoLost = 3;  // unanswered in a row: the echo has gone, and every call would wait 1 s
  Block block;
  block.skilld.us.reserve(calls);
  block.echo.us.reserve(calls);
  auto next = Clock::now();
  int echo_unanswered_in_a_row = 0;
  const auto time_echo = [&] {
    const int before = block.echo.unanswered;
    block.echo.Time(*echo);
    echo_unanswered_in_a_row = block.echo.unanswered > before ? echo_unanswered_in_a_row + 1 : 0;
    if (echo_unanswered_in_a_row >= kEchoLost) {
      throw InputError("skillctl bench: its echo stopped answering (" + std::to_string(kEchoLost) + " calls in a row)");
    }
  };
  for (int i = 0; i < calls; ++i) {
    std::this_thread::sleep_until(next);
    // A call that was due while this thread did not run is not made up for by a burst: bursts
    // beyond skilld's rate limit (requests_per_second, request_burst) are dropped unanswered.
    next = std::max(next + period, Clock::now());
    if (echo != nullptr && i % 2 == 1) time_echo();
    block.skilld.Time(skilld);
    if (echo != nullptr && i % 2 == 0) time_echo();
  }
  return block;
}

// p50 / peer_p50, or nullopt when either side has no answered call to time.
std::optional<double> RatioOfMedians(const std::vector<double>& us, double peer_p50) {
  if (us.empty() || !(peer_p50 > 0.0)) return std::nullopt;
  return Quantile(us, 0.5) / peer_p50;
}

// The echo (request_echo.h) in a process of its own, as skilld is: `skillctl bench-echo`.
std::unique_ptr<ChildProcess> StartEcho(int domain_id, const std::string& partition, long seconds) {
  return std::make_unique<ChildProcess>(
      std::vector<std::string>{ProgramPath(), "--domain", std::to_string(domain_id), "--partition",
                               EchoPartition(partition), "bench-echo", "--seconds", std::to_string(seconds)},
      "/dev/null");
}

}  // namespace

nlohmann::json RunDdsBenchmark(Client& client, int domain_id, const DdsBenchOptions& options) {
  const int calls_per_block = static_cast<int>(options.rate_hz * options.block_seconds);
  // The echo outlives any run of the bench that finishes: blocks stretch on a busy machine.
  const long seconds = 3L * options.blocks * (2 * options.block_seconds + 2) + 60;
  // With DDS Security the echo would need an identity of its own with skilld's permissions: the
  // secured run compares against ddsperf only.
  std::unique_ptr<ChildProcess> echo_process;
  std::unique_ptr<Client> echo;
  if (!options.security.enabled) {
    echo_process = StartEcho(domain_id, options.partition, seconds);
    Client::Options echo_options;
    echo_options.domain_id = domain_id;
    echo_options.partition = EchoPartition(options.partition);
    echo = std::make_unique<Client>(echo_options);
    if (!echo->WaitForServer(std::chrono::seconds(10))) throw InputError("skillctl bench: its echo did not answer");
  }
  StatusRoundTrips(client, echo.get(), 100, options.rate_hz);  // warm-up
  std::vector<double> all_us, all_echo_us, ratios, echo_ratios, ddsperf_p50s, ddsperf_p99s;
  nlohmann::json blocks = nlohmann::json::array();
  int unanswered = 0, echo_unanswered = 0;
  long ddsperf_round_trips = 0;
  {
    const ExtraCycloneConfig config(dds::SecurityXml(options.security));
    // One pong for every block, with room for each ping's start.
    const DdsperfPong pong(domain_id, options.blocks * (2 * options.block_seconds + 2) + 10);
    for (int b = 0; b < options.blocks; ++b) {
      const Block calls = StatusRoundTrips(client, echo.get(), calls_per_block, options.rate_hz);
      const PingResult ping = Ping(domain_id, options.block_seconds, options.rate_hz);
      const double ddsperf_p50 = 2.0 * ping.p50_us;
      unanswered += calls.skilld.unanswered;
      echo_unanswered += calls.echo.unanswered;
      all_us.insert(all_us.end(), calls.skilld.us.begin(), calls.skilld.us.end());
      all_echo_us.insert(all_echo_us.end(), calls.echo.us.begin(), calls.echo.us.end());
      ddsperf_p50s.push_back(ddsperf_p50);
      ddsperf_p99s.push_back(2.0 * ping.p99_us);
      ddsperf_round_trips += ping.count;
      // A block without an answered call (skilld's or the echo's) has no ratio: it is left out.
      nlohmann::json block = {{"rtt_p50_us", Quantile(calls.skilld.us, 0.5)},
                              {"rtt_p99_us", Quantile(calls.skilld.us, 0.99)},
                              {"ddsperf_rtt_p50_us", ddsperf_p50}};
      if (const std::optional<double> r = RatioOfMedians(calls.skilld.us, ddsperf_p50)) {
        ratios.push_back(*r);
        block["ratio"] = *r;
      }
      if (echo) {
        block["echo_rtt_p50_us"] = Quantile(calls.echo.us, 0.5);
        if (const std::optional<double> r = RatioOfMedians(calls.skilld.us, Quantile(calls.echo.us, 0.5))) {
          echo_ratios.push_back(*r);
          block["ratio_to_echo"] = *r;
        }
      }
      blocks.push_back(block);
    }
  }
  if (ratios.empty()) throw InputError("skillctl bench: no block had an answered call to skilld and a ddsperf round trip");
  const double ratio = Quantile(ratios, 0.5);
  nlohmann::json result = {
      {"benchmark", "skillctl bench"},
      {"rate_hz", options.rate_hz},
      {"blocks", options.blocks},
      {"block_seconds", options.block_seconds},
      {"calls", all_us.size() + unanswered},
      {"unanswered", unanswered},
      {"rtt_min_us", Quantile(all_us, 0.0)},
      {"rtt_p50_us", Quantile(all_us, 0.5)},
      {"rtt_p99_us", Quantile(all_us, 0.99)},
      {"ddsperf_rtt_p50_us", Quantile(ddsperf_p50s, 0.5)},
      {"ddsperf_rtt_p99_us", Quantile(ddsperf_p99s, 0.5)},
      {"ddsperf_round_trips", ddsperf_round_trips},
      {"ratio", ratio},  // the median of the blocks' ratios
      {"ratio_min", Quantile(ratios, 0.0)},
      {"ratio_max", Quantile(ratios, 1.0)},
      {"ratio_spread", Quantile(ratios, 1.0) - Quantile(ratios, 0.0)},
      {"per_block", blocks},
      {"target_ratio_at_most", 1.5},
      {"machine", MachineDescription()},
      {"dds_security", options.security.enabled},
  };
  if (echo) {  // skilld's calls against the echo's, interleaved call by call
    result["echo_calls"] = all_echo_us.size() + echo_unanswered;
    result["echo_unanswered"] = echo_unanswered;
    result["echo_rtt_p50_us"] = Quantile(all_echo_us, 0.5);
    result["echo_rtt_p99_us"] = Quantile(all_echo_us, 0.99);
    result["ratio_to_echo"] = Quantile(echo_ratios, 0.5);
    result["ratio_to_echo_min"] = Quantile(echo_ratios, 0.0);
    result["ratio_to_echo_max"] = Quantile(echo_ratios, 1.0);
    result["ratio_to_echo_spread"] = Quantile(echo_ratios, 1.0) - Quantile(echo_ratios, 0.0);
  }
  if (options.security.enabled) {  // what authentication and encryption add to a DDS round trip
    const DdsperfPong pong(domain_id, options.block_seconds + 3);
    const PingResult plain = Ping(domain_id, options.block_seconds, options.rate_hz);
    result["ddsperf_unsecured_rtt_p50_us"] = 2.0 * plain.p50_us;
    result["ddsperf_unsecured_rtt_p99_us"] = 2.0 * plain.p99_us;
    result["security_cost_p50_us"] = result["ddsperf_rtt_p50_us"].get<double>() - 2.0 * plain.p50_us;
  }
  return result;
}

}  // namespace flsd
