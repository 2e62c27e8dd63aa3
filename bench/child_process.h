#pragma once
// A program a benchmark starts and watches: skilld, the robot emulator, clients, a training run.

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace flsd {

// The folder of the running executable, where the build puts its sibling programs.
std::string SiblingProgram(const std::string& name);

class ChildProcess {
 public:
  // Starts args[0] (a path, or a name looked up in PATH) with `args`; its stdout goes to `out_path`, its stderr to `err_path` (empty:
  // to `out_path` too). Throws InputError if the program cannot be started.
  ChildProcess(const std::vector<std::string>& args, const std::string& out_path, const std::string& err_path = "");
  ~ChildProcess();  // SIGKILL if it still runs
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  // Whether it still runs; once it has exited, exit_status() says how.
  bool Running();
  // Sends `signal`, waits `grace` for the exit, then SIGKILLs; returns the exit status.
  int Stop(int signal, std::chrono::milliseconds grace);
  // waitpid's status once it exited; nullopt while it runs.
  const std::optional<int>& exit_status() const { return status_; }

 private:
  pid_t pid_ = 0;
  std::optional<int> status_;
};

// "exit code 3", "killed by Segmentation fault": a waitpid status for people.
std::string DescribeExit(int status);

}  // namespace flsd
