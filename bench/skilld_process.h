#pragma once
// The benchmarks that measure what a user gets (flsd bench nav, flsd bench vel) start a real
// skilld and drive it over DDS on loopback.

#include <sys/types.h>

#include <memory>
#include <string>

#include "client/client.h"

namespace flsd {

// skilld with the simulated A1 and `library` (and the server config `config`, if not empty: else
// skilld's default, configs/server.yaml) for
// the length of a benchmark, its log in a file, in a partition of its own on `domain_id`, reached
// only over loopback (unless the user has configured Cyclone otherwise).
class SkilldProcess {
 public:
  SkilldProcess(const std::string& library, const std::string& config, int domain_id, const std::string& name);
  ~SkilldProcess();  // SIGINT: skilld damps the robot and leaves
  SkilldProcess(const SkilldProcess&) = delete;
  SkilldProcess& operator=(const SkilldProcess&) = delete;

  // A client of this server holding its control lease; throws InputError naming the log if the
  // server does not answer within 60 s.
  std::unique_ptr<Client> Connect() const;
  const std::string& log() const { return log_; }

 private:
  int domain_id_;
  std::string partition_, log_;
  pid_t pid_ = 0;
};

// Resets the simulated robot to its start pose and waits (up to 5 s) until the state says so.
void ResetAndWait(Client& client);

}  // namespace flsd
