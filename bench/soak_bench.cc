#include "bench/soak_bench.h"

#include <signal.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <system_error>
#include <thread>
#include <vector>

#include "bench/child_process.h"
#include "bench/machine.h"
#include "bench/process_stats.h"
#include "bench/skilld_process.h"
#include "bench/stats.h"
#include "core/check.h"
#include "core/paths.h"
#include "server/server_config.h"

namespace flsd {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double kSampleSeconds = 5.0;   // skilld's RSS, threads and descriptors
constexpr double kSeriesSeconds = 30.0;  // RSS samples kept in the report
constexpr double kWarmUpSeconds = 60.0;  // allocations that settle in the first minute are no leak
constexpr int kExamples = 10;

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A folder for the run's files, removed at the end: a new one of its own (mkdtemp: mode 0700), as
// it holds the run's private keys, and a name known in advance could be taken by another user.
class RunFolder {
 public:
  RunFolder() {
    std::string name = (fs::temp_directory_path() / "flsd-soak-XXXXXX").string();
    if (mkdtemp(name.data()) == nullptr) throw std::system_error(errno, std::generic_category(), "mkdtemp " + name);
    path_ = name;
  }
  ~RunFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

std::string ClientName(int i) { return "soak" + std::to_string(i); }

// A deployment of its own: skilld's identity and one operator per client.
void MakePki(const fs::path& dir, int clients) {
  std::string operators;
  for (int i = 0; i < clients; ++i) operators += (i > 0 ? " " : "") + ClientName(i);
  const std::string command = "bash " + ResolveDataPath("scripts/make_pki.sh") + " " + dir.string() +
                              " --operators '" + operators + "' --observers '' > " + (dir.string() + ".log") + " 2>&1";
  if (std::system(command.c_str()) != 0) throw InputError("make_pki.sh failed: " + ReadText(dir.string() + ".log"));
}

// The robot emulator on a free loopback port, dropping 5 % of its state frames and corrupting
// 2 % once skilld's pre-flight has passed; returns its port.
int StartEmulator(std::unique_ptr<ChildProcess>& emulator, const fs::path& log) {
  emulator = std::make_unique<ChildProcess>(
      std::vector<std::string>{SiblingProgram("a1_emulator"), "--port", "0", "--drop", "0.05", "--corrupt", "0.02",
                               "--faults-after", "5"},
      log.string());
  const std::regex listening(R"(listening on [0-9.]+:(\d+))");
  for (int i = 0; i < 500; ++i) {
    std::smatch m;
    const std::string text = ReadText(log);
    if (std::regex_search(text, m, listening)) return std::stoi(m[1]);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  throw InputError("a1_emulator did not start: " + ReadText(log));
}

// skilld's config: the demo map for navigate without one, and the robot or the security asked for.
// Other clients may clear a stop 0.1 s after its press (the shipped hold is 10 s): with clients
// pressing several times a second, a 10-s hold kept the stop latched for the whole run, and no damp
// found a robot to stop (3 damp latencies in an hour). 0.1 s is 5 ticks, so a press always shows in
// the state topic before another client's clear can undo it.
std::string SoakServerConfig(const SoakBenchOptions& o, int emulator_port, const fs::path& pki) {
  std::string yaml = "navigation:\n  map: " + ResolveDataPath("configs/maps/demo.yaml") + "\n" +
                     "safety:\n  stop_hold_time: 0.1\n";
  if (o.backend == "hw") {
    yaml += "hw:\n  local_host: 127.0.0.1\n  local_port: 0\n  robot_host: 127.0.0.1\n  robot_port: " +
            std::to_string(emulator_port) + "\n  preflight_seconds: 0.3\n";
  }
  if (o.security) yaml += ReadText(pki / "skilld" / "security.yaml");
  return yaml;
}

struct Sample {
  double t = 0.0;  // s since the clients started
  ProcessSample process;
};

// skilld's resources from the first minute (or the second half of a shorter run) on.
nlohmann::json Resources(const std::vector<Sample>& samples, double run_seconds) {
  const double from = std::min(kWarmUpSeconds, run_seconds / 2);
  std::vector<double> t, rss, anon;
  nlohmann::json series = nlohmann::json::array();
  double next_series = 0.0;
  for (const Sample& s : samples) {
    if (s.t >= next_series) {
      series.push_back({std::round(s.t), std::round(s.process.rss_mb * 100) / 100});
      next_series += kSeriesSeconds;
    }
    if (s.t < from) continue;
    t.push_back(s.t);
    rss.push_back(s.process.rss_mb);
    anon.push_back(s.process.rss_anon_mb);
  }
  const auto first = std::find_if(samples.begin(), samples.end(), [&](const Sample& s) { return s.t >= from; });
  if (first == samples.end()) return {{"error", "no sample after " + std::to_string(from) + " s"}};
  const ProcessSample& start = first->process;
  const ProcessSample& end = samples.back().process;
  return {{"from_s", from},
          {"rss_mb_start", start.rss_mb},
          {"rss_mb_end", end.rss_mb},
          {"rss_slope_mb_per_hour", Slope(t, rss) * 3600.0},
          {"rss_anon_mb_start", start.rss_anon_mb},
          {"rss_anon_mb_end", end.rss_anon_mb},
          {"rss_anon_slope_mb_per_hour", Slope(t, anon) * 3600.0},
          {"rss_file_mb_start", start.rss_file_mb},
          {"rss_file_mb_end", end.rss_file_mb},
          {"fds_start", start.fds},
          {"fds_end", end.fds},
          {"threads_start", start.threads},
          {"threads_end", end.threads},
          {"rss_mb_series", series}};
}

// skilld's exit line: "skilld stopped after N ticks, M deadline misses, R replies; tick lateness
// p50 X ms, p99 Y ms, worst Z ms". Null if it did not say it.
nlohmann::json TickLateness(const std::string& log) {
  const std::regex line(
      R"(stopped after (\d+) ticks, (\d+) deadline misses, (\d+) replies; tick lateness p50 ([0-9.]+) ms, p99 ([0-9.]+) ms, worst ([0-9.]+) ms)");
  std::smatch m;
  if (!std::regex_search(log, m, line)) return nullptr;
  return {{"ticks", std::stoll(m[1])}, {"deadline_misses", std::stoll(m[2])}, {"replies", std::stoll(m[3])},
          {"p50_ms", std::stod(m[4])}, {"p99_ms", std::stod(m[5])}, {"max_ms", std::stod(m[6])}};
}

void AddExamples(nlohmann::json& into, const nlohmann::json& from) {
  for (const auto& e : from) {
    if (into.size() < kExamples) into.push_back(e);
  }
}

}  // namespace

nlohmann::json RunSoakBenchmark(const SoakBenchOptions& o) {
  const RunFolder folder;
  const double run_seconds = o.minutes * 60.0;
  if (o.security) MakePki(folder / "pki", o.clients);
  std::unique_ptr<ChildProcess> emulator;
  const int port = o.backend == "hw" ? StartEmulator(emulator, folder / "emulator.log") : 0;
  const fs::path config = folder / "server.yaml";
  std::ofstream(config) << SoakServerConfig(o, port, folder / "pki");
  SkilldProcess skilld(o.library, config.string(), o.domain_id, "soak", o.backend);
  // The clients' oracle knows the lease and the motions' limit as skilld reads them.
  const ServerConfig server = LoadServerConfig(config.string());

  std::unique_ptr<ChildProcess> training;
  if (o.beside_training) {
    training = std::make_unique<ChildProcess>(
        std::vector<std::string>{SiblingProgram("flsd"), "train", "--config", ResolveDataPath("configs/smoke.yaml"),
                                 "--threads", "1", "--iterations", "100000000", "--out", (folder / "train").string()},
        (folder / "train.log").string());
  }
  std::vector<std::unique_ptr<ChildProcess>> clients;
  for (int i = 0; i < o.clients; ++i) {
    std::vector<std::string> args = {SiblingProgram("soak_client"), "--domain", std::to_string(o.domain_id),
                                     "--partition", skilld.partition(), "--name", ClientName(i),
                                     "--seed", std::to_string(o.seed * 1000 + i), "--seconds", std::to_string(run_seconds),
                                     "--rate", std::to_string(o.rate_hz),
                                     "--lease-timeout", std::to_string(server.lease_timeout),
                                     "--max-duration", std::to_string(server.max_duration)};
    if (o.security) args.insert(args.end(), {"--security", (folder / "pki" / ClientName(i) / "security.yaml").string()});
    if (!o.heavy_maps) args.push_back("--light-maps");
    if (o.backend == "hw") args.push_back("--no-reset");
    clients.push_back(std::make_unique<ChildProcess>(args, (folder / (ClientName(i) + ".json")).string(),
                                                     (folder / (ClientName(i) + ".err")).string()));
  }

  // Watch skilld until the clients are done (they wait up to 30 s for it, then run their time).
  nlohmann::json crashes = nlohmann::json::array();
  std::vector<Sample> samples;
  const auto started = Clock::now();
  const auto seconds_since_start = [&] { return std::chrono::duration<double>(Clock::now() - started).count(); };
  for (double next_sample = 0.0;;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    if (!skilld.process().Running()) {
      crashes.push_back("skilld: " + DescribeExit(*skilld.process().exit_status()) + " during the run");
      break;
    }
    if (seconds_since_start() >= next_sample) {
      if (const std::optional<ProcessSample> s = SampleProcess(skilld.process().pid())) {
        samples.push_back({seconds_since_start(), *s});
      }
      next_sample += kSampleSeconds;
    }
    const bool clients_done =
        std::none_of(clients.begin(), clients.end(), [](const auto& c) { return c->Running(); });
    if (clients_done || seconds_since_start() > run_seconds + 90.0) break;
  }
  int64_t training_iterations = -1;
  if (training) {
    if (!training->Running()) crashes.push_back("flsd train: " + DescribeExit(*training->exit_status()));
    training->Stop(SIGKILL, std::chrono::milliseconds(0));
    std::istringstream progress(ReadText(folder / "train" / "progress.csv"));
    for (std::string line; std::getline(progress, line);) ++training_iterations;  // the header is not one
  }

  nlohmann::json total = {{"requests", 0}, {"answered", 0}, {"dropped", 0},
                          {"late", 0},     {"wrong", 0},    {"state_checks", 0}};
  nlohmann::json wrong_examples = nlohmann::json::array(), dropped_examples = nlohmann::json::array();
  nlohmann::json statuses = nlohmann::json::object();
  std::vector<double> damp_ms;
  uint64_t server_dropped = 0;
  for (int i = 0; i < o.clients; ++i) {
    ChildProcess& c = *clients[i];
    const int status = c.Stop(SIGKILL, std::chrono::milliseconds(0));
    const std::string name = ClientName(i);
    const std::string out = ReadText(folder / (name + ".json"));
    const nlohmann::json tally = nlohmann::json::parse(out, nullptr, /*allow_exceptions=*/false);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || tally.is_discarded()) {
      crashes.push_back(name + ": " + DescribeExit(status) + ": " + ReadText(folder / (name + ".err")).substr(0, 500));
      continue;
    }
    for (const char* key : {"requests", "answered", "dropped", "late", "wrong", "state_checks"}) {
      total[key] = total[key].get<int64_t>() + tally[key].get<int64_t>();
    }
    AddExamples(wrong_examples, tally["wrong_examples"]);
    AddExamples(dropped_examples, tally["dropped_examples"]);
    for (const auto& [status_name, n] : tally["statuses"].items()) {
      statuses[status_name] = statuses.value(status_name, int64_t{0}) + n.get<int64_t>();
    }
    for (double ms : tally["damp_latency_ms"]) damp_ms.push_back(ms);
    server_dropped = std::max(server_dropped, tally["server_requests_dropped"].get<uint64_t>());
  }

  const bool skilld_was_running = skilld.process().Running();
  const int skilld_status = skilld.Stop();
  if (skilld_was_running && (!WIFEXITED(skilld_status) || WEXITSTATUS(skilld_status) != 0)) {
    crashes.push_back("skilld: " + DescribeExit(skilld_status) + " on SIGINT");
  }
  if (emulator) emulator->Stop(SIGINT, std::chrono::seconds(2));
  const std::string skilld_log = ReadText(skilld.log());
  if (crashes.empty()) std::remove(skilld.log().c_str());

  nlohmann::json result = {
      {"benchmark", "soak"},
      {"minutes", o.minutes},
      {"clients", o.clients},
      {"rate_hz_per_client", o.rate_hz},
      {"backend", o.backend},
      {"dds_security", o.security},
      {"beside_training", o.beside_training},
      {"heavy_maps", o.heavy_maps},
      {"requests", total["requests"]},
      {"answered", total["answered"]},
      {"wrong_replies", total["wrong"]},
      {"wrong_examples", wrong_examples},
      {"dropped", total["dropped"]},
      {"dropped_examples", dropped_examples},
      {"late_replies", total["late"]},
      {"crashes", crashes.size()},
      {"crash_details", crashes},
      {"statuses", statuses},
      {"state_checks", total["state_checks"]},
      {"requests_dropped_by_server", server_dropped},
      {"skilld", Resources(samples, run_seconds)},
      {"tick_lateness_ms", TickLateness(skilld_log)},
      {"passed", total["wrong"].get<int64_t>() == 0 && total["dropped"].get<int64_t>() == 0 && crashes.empty()},
      {"damp_latency_ms",
       {{"count", damp_ms.size()}, {"p50", Quantile(damp_ms, 0.5)}, {"p99", Quantile(damp_ms, 0.99)},
        {"max", Quantile(damp_ms, 1.0)}}},
      {"machine", MachineDescription()},
  };
  if (!crashes.empty()) result["skilld_log"] = skilld.log();
  if (training) result["training_iterations"] = training_iterations;
  return result;
}

}  // namespace flsd
