#pragma once
// skillweb as a child process of a test, on a free port of the loopback interface.

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "tests/common/process.h"

namespace flsd::testutil {

struct Skillweb {
  std::unique_ptr<Process> process;
  std::string url;  // http(s)://127.0.0.1:PORT/, empty if it did not start
  int port = 0;
};

// Starts skillweb with `args` (and --port 0) and waits for the address it prints.
inline Skillweb StartSkillweb(std::vector<std::string> args, const std::string& log_path) {
  args.insert(args.end(), {"--port", "0"});
  Skillweb web;
  web.process = std::make_unique<Process>(BinaryPath("skillweb"), args, log_path);
  const std::regex address("https?://127\\.0\\.0\\.1:([0-9]+)/");
  for (int i = 0; i < 100 && web.url.empty(); ++i) {
    std::smatch m;
    const std::string text = web.process->Log();
    if (std::regex_search(text, m, address)) {
      web.url = m.str();
      web.port = std::stoi(m[1]);
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  if (web.url.empty()) ADD_FAILURE() << "skillweb did not start: " << web.process->Log();
  return web;
}

}  // namespace flsd::testutil
