#pragma once
// The benchmarks that measure what a user gets (flsd bench nav, flsd bench vel) start a real
// skilld and drive it over DDS on loopback.

#include <memory>
#include <string>

#include "bench/child_process.h"
#include "client/client.h"

namespace flsd {

// skilld with `library` on `backend` (sim: the simulated A1; hw: the robot `config` names), with
// the server config `config` if not empty (else skilld's default, configs/server.yaml), for the
// length of a benchmark, its log in a file, in a partition of its own on `domain_id`, reached only
// over loopback (unless the user has configured Cyclone otherwise).
class SkilldProcess {
 public:
  SkilldProcess(const std::string& library, const std::string& config, int domain_id, const std::string& name,
                const std::string& backend = "sim");
  ~SkilldProcess() { Stop(); }
  SkilldProcess(const SkilldProcess&) = delete;
  SkilldProcess& operator=(const SkilldProcess&) = delete;

  // A client of this server holding its control lease; throws InputError naming the log if the
  // server does not answer within 60 s.
  std::unique_ptr<Client> Connect() const;
  const std::string& log() const { return log_; }
  const std::string& partition() const { return partition_; }
  ChildProcess& process() { return *process_; }
  // SIGINT: skilld damps the robot and leaves (SIGKILL after 5 s). Its exit status.
  int Stop();

 private:
  int domain_id_;
  std::string partition_, log_;
  std::unique_ptr<ChildProcess> process_;
};

// Resets the simulated robot to its start pose and waits (up to 5 s) until the state says so.
void ResetAndWait(Client& client);

}  // namespace flsd
