#pragma once
// Runs a program of this build as a child process, for integration tests of skilld and skillctl.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace flsd::testutil {

inline std::string BinaryPath(const std::string& name) { return std::string(FLSD_BIN_DIR) + "/" + name; }

class Process {
 public:
  // Starts `program` (a path) with `args`; its stdout and stderr go to `log_path`.
  Process(const std::string& program, const std::vector<std::string>& args, const std::string& log_path)
      : log_path_(log_path) {
    pid_ = fork();
    if (pid_ == 0) {
      const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(fd, 1);
      dup2(fd, 2);
      std::vector<char*> argv;
      argv.push_back(const_cast<char*>(program.c_str()));
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(program.c_str(), argv.data());
      _exit(127);
    }
  }
  ~Process() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  void Signal(int signal) { kill(pid_, signal); }

  // Waits for the exit; returns the exit code, 128 + signal if killed, -1 on timeout.
  int Wait(std::chrono::milliseconds timeout = std::chrono::milliseconds(10000)) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < until) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return -1;
  }

  std::string Log() const {
    std::ifstream in(log_path_);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }

 private:
  pid_t pid_ = -1;
  bool exited_ = false;
  std::string log_path_;
};

// Runs a program to its end; returns its exit code and output.
inline std::pair<int, std::string> RunProgram(const std::string& program, const std::vector<std::string>& args,
                                              const std::string& log_path,
                                              std::chrono::milliseconds timeout = std::chrono::milliseconds(30000)) {
  Process p(program, args, log_path);
  const int code = p.Wait(timeout);
  return {code, p.Log()};
}

}  // namespace flsd::testutil
