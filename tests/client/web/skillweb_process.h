#pragma once
// skillweb as a child process of a test, on a free port of the loopback interface.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
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

// The password the tests give user `name`.
inline std::string TestPassword(const std::string& name) { return name + "-password"; }

// For skillweb over HTTPS with logins: a self-signed certificate for 127.0.0.1 (DIR/cert.pem,
// DIR/key.pem) and DIR/users with each {name, role}, added by `skillweb --add-user` as the docs
// say, with TestPassword; with `identities`, each user's make_pki.sh identity is the one of its name.
inline void MakeHttpsLogins(const std::string& dir, const std::vector<std::pair<std::string, std::string>>& users,
                            bool identities = false) {
  const std::string cert = "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days 1 "
                           "-subj /CN=127.0.0.1 -keyout " + dir + "/key.pem -out " + dir + "/cert.pem 2> /dev/null";
  ASSERT_EQ(std::system(cert.c_str()), 0);
  for (const auto& [name, role] : users) {
    const std::string add = "printf '" + TestPassword(name) + "\\n' | " + BinaryPath("skillweb") + " --users " + dir +
                            "/users --add-user " + name + " --role " + role + " --identity " +
                            (identities ? name : "-") + " > /dev/null";
    ASSERT_EQ(std::system(add.c_str()), 0) << add;
  }
}

// skillweb's arguments for MakeHttpsLogins' files.
inline std::vector<std::string> HttpsLoginArgs(const std::string& dir) {
  return {"--tls-cert", dir + "/cert.pem", "--tls-key", dir + "/key.pem", "--users", dir + "/users"};
}

}  // namespace flsd::testutil
