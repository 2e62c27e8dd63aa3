#include "bench/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <thread>

#include "core/check.h"
#include "core/paths.h"

extern char** environ;

namespace flsd {

std::string SiblingProgram(const std::string& name) {
  return (std::filesystem::path(ProgramPath()).parent_path() / name).string();
}

ChildProcess::ChildProcess(const std::vector<std::string>& args, const std::string& out_path,
                           const std::string& err_path) {
  FLSD_DEMAND(!args.empty());
  std::vector<std::string> owned = args;
  std::vector<char*> argv;
  for (std::string& a : owned) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t output;
  posix_spawn_file_actions_init(&output);
  posix_spawn_file_actions_addopen(&output, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (err_path.empty()) {
    posix_spawn_file_actions_adddup2(&output, 1, 2);
  } else {
    posix_spawn_file_actions_addopen(&output, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  }
  const int spawned = posix_spawnp(&pid_, args[0].c_str(), &output, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&output);
  if (spawned != 0) throw InputError("cannot start " + args[0] + ": " + std::strerror(spawned) + " (build it first)");
}

ChildProcess::~ChildProcess() {
  if (Running()) Stop(SIGKILL, std::chrono::milliseconds(0));
}

bool ChildProcess::Running() {
  if (status_) return false;
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) != pid_) return true;
  status_ = status;
  return false;
}

int ChildProcess::Stop(int signal, std::chrono::milliseconds grace) {
  if (Running()) kill(pid_, signal);
  const auto until = std::chrono::steady_clock::now() + grace;
  while (Running() && std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (Running()) {
    kill(pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
    status_ = status;
  }
  return *status_;
}

std::string DescribeExit(int status) {
  if (WIFSIGNALED(status)) return std::string("killed by ") + strsignal(WTERMSIG(status));
  return "exit code " + std::to_string(WEXITSTATUS(status));
}

}  // namespace flsd
