#include "bench/skilld_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
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

extern char** environ;

namespace flsd {

namespace fs = std::filesystem;

SkilldProcess::SkilldProcess(const std::string& library, const std::string& config, int domain_id,
                             const std::string& name)
    : domain_id_(domain_id), partition_(name + "-" + std::to_string(getpid())) {
  const std::string loopback = "file://" + ResolveDataPath("configs/cyclonedds_loopback.xml");
  setenv("CYCLONEDDS_URI", loopback.c_str(), /*overwrite=*/0);
  log_ = (fs::temp_directory_path() / (partition_ + ".log")).string();
  const std::string skilld = (fs::read_symlink("/proc/self/exe").parent_path() / "skilld").string();
  const std::string resolved = ResolveDataPath(library);
  const std::string domain = std::to_string(domain_id);
  std::vector<std::string> args = {skilld, "--backend", "sim", "--library", resolved, "--domain", domain,
                                   "--partition", partition_};
  if (!config.empty()) args.insert(args.end(), {"--config", ResolveDataPath(config)});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t output;
  posix_spawn_file_actions_init(&output);
  posix_spawn_file_actions_addopen(&output, 1, log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&output, 1, 2);
  const int spawned = posix_spawn(&pid_, skilld.c_str(), &output, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&output);
  if (spawned != 0) throw InputError("cannot start " + skilld + ": build it first (make build)");
}

SkilldProcess::~SkilldProcess() {
  kill(pid_, SIGINT);
  for (int i = 0; i < 100 && waitpid(pid_, nullptr, WNOHANG) == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (kill(pid_, 0) == 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
}

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
