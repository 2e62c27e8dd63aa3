#include "bench/process_stats.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace flsd {

std::optional<ProcessSample> SampleProcess(pid_t pid) {
  const std::string proc = "/proc/" + std::to_string(pid);
  std::ifstream status(proc + "/status");
  if (!status) return std::nullopt;
  ProcessSample s;
  for (std::string line; std::getline(status, line);) {
    // "VmRSS:  1234 kB"
    if (line.rfind("VmRSS:", 0) == 0) s.rss_mb = std::stod(line.substr(6)) / 1024.0;
    if (line.rfind("RssAnon:", 0) == 0) s.rss_anon_mb = std::stod(line.substr(8)) / 1024.0;
    if (line.rfind("RssFile:", 0) == 0) s.rss_file_mb = std::stod(line.substr(8)) / 1024.0;
    if (line.rfind("Threads:", 0) == 0) s.threads = std::stoi(line.substr(8));
  }
  std::error_code error;
  for (std::filesystem::directory_iterator fd(proc + "/fd", error), end; !error && fd != end; fd.increment(error)) {
    ++s.fds;
  }
  if (error) return std::nullopt;
  return s;
}

}  // namespace flsd
