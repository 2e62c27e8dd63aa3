#include "bench/skilld_process.h"

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "core/check.h"
#include "core/paths.h"

namespace flsd {

namespace fs = std::filesystem;

SkilldProcess::SkilldProcess(const std::string& library, const std::string& config, int domain_id,
                             const std::string& name, const std::string& backend)
    : domain_id_(domain_id), partition_(name + "-" + std::to_string(getpid())) {
  const std::string loopback = "file://" + ResolveDataPath("configs/cyclonedds_loopback.xml");
  setenv("CYCLONEDDS_URI", loopback.c_str(), /*overwrite=*/0);
  log_ = (fs::temp_directory_path() / (partition_ + ".log")).string();
  std::vector<std::string> args = {SiblingProgram("skilld"), "--backend", backend, "--library", ResolveDataPath(library),
                                   "--domain", std::to_string(domain_id), "--partition", partition_};
  if (!config.empty()) args.insert(args.end(), {"--config", ResolveDataPath(config)});
  process_ = std::make_unique<ChildProcess>(args, log_);
}

int SkilldProcess::Stop() { return process_->Stop(SIGINT, std::chrono::seconds(5)); }

std::unique_ptr<Client> SkilldProcess::Connect() const {
  Client::Options options;
  options.domain_id = domain_id_;
  options.partition = partition_;
  auto client = std::make_unique<Client>(options);
  if (!client->WaitForServer(std::chrono::seconds(60))) {
    throw InputError("skilld did not answer within 60 s (its log: " + log_ + ")");
  }
  const Reply control = client->AcquireControl();
  if (!control.ok()) throw InputError("acquire_control: " + control.Describe());
  return client;
}

void ResetAndWait(Client& client) {
  const Reply reset = client.Reset();
  if (!reset.ok()) throw InputError("reset: " + reset.Describe());
  // The controller applies the reset at its next tick.
  const auto reset_by = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  for (uint64_t tick = 0; std::chrono::steady_clock::now() < reset_by;) {
    const std::optional<StateReport> state = client.NextState(tick, std::chrono::milliseconds(500));
    if (!state) continue;
    tick = state->tick;
    // Back at the origin with no fault latched: a robot that fell there is not yet reset.
    if (state->faults == 0 && std::hypot(state->position[0], state->position[1]) < 0.05) return;
  }
}

}  // namespace flsd
