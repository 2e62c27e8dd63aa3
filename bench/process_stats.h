#pragma once
// What a long-running process holds, read from /proc: for soak runs that look for leaks.

#include <sys/types.h>

#include <optional>

namespace flsd {

struct ProcessSample {
  double rss_mb = 0.0;       // resident set, MiB
  double rss_anon_mb = 0.0;  // of which anonymous (heap, stacks): what a leak grows
  double rss_file_mb = 0.0;  // of which file-backed (code and data of the binary and libraries, paged in as used)
  int threads = 0;
  int fds = 0;  // open file descriptors
};

// nullopt once the process is gone.
std::optional<ProcessSample> SampleProcess(pid_t pid);

}  // namespace flsd
