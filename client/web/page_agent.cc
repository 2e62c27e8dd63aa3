#include "client/web/page_agent.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <iostream>
#include <stdexcept>
#include <vector>

namespace flsd::web {
namespace {

using nlohmann::json;

constexpr std::chrono::seconds kStartTimeout{20}, kReplyTimeout{30};

// One line from the agent, without its newline; false at its end.
bool ReadLine(FILE* in, std::string& line) {
  line.clear();
  for (int c; (c = std::fgetc(in)) != EOF;) {
    if (c == '\n') return true;
    line += static_cast<char>(c);
  }
  return false;
}

bool WriteAll(int fd, const std::string& text) {
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

json Unavailable(int& status, const std::string& why) {
  status = 503;
  return json{{"ok", false}, {"status", "refused"}, {"message", why}, {"audit", "refused: " + why}};
}

}  // namespace

AgentPageLink::AgentPageLink(const AgentOptions& options) {
  std::vector<std::string> args = {options.program, "--page-agent", "--domain", std::to_string(options.domain_id),
                                   "--partition", options.partition};
  if (!options.security_file.empty()) args.insert(args.end(), {"--security", options.security_file});
  if (options.read_only) args.push_back("--read-only");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  int in[2], out[2];
  if (pipe2(in, O_CLOEXEC) != 0) throw std::runtime_error("page agent: pipe2 failed");
  if (pipe2(out, O_CLOEXEC) != 0) {
    close(in[0]);
    close(in[1]);
    throw std::runtime_error("page agent: pipe2 failed");
  }
  pid_ = fork();
  if (pid_ == 0) {  // only async-signal-safe calls until exec
    dup2(in[0], STDIN_FILENO);
    dup2(out[1], STDOUT_FILENO);
    close_range(3, ~0U, 0);  // nothing of skillweb's: its listening socket, the other pages' pipes
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(in[0]);
  close(out[1]);
  to_agent_ = in[1];
  from_agent_ = fdopen(out[0], "r");
  if (pid_ < 0 || !from_agent_) {
    Stop();
    throw std::runtime_error("page agent: cannot start " + options.program);
  }
  pollfd ready{fileno(from_agent_), POLLIN, 0};
  std::string line;
  const bool answered = poll(&ready, 1, static_cast<int>(kStartTimeout.count() * 1000)) == 1 && ReadLine(from_agent_, line);
  if (!answered || line.rfind("I ", 0) != 0) {
    Stop();
    throw std::runtime_error(line.rfind("X ", 0) == 0 ? line.substr(2) : "its DDS client did not start");
  }
  id_ = line.substr(2);
  reader_ = std::thread([this] { Read(); });
}

AgentPageLink::~AgentPageLink() {
  Stop();
  if (reader_.joinable()) reader_.join();
}

void AgentPageLink::Stop() {
  if (to_agent_ >= 0) close(to_agent_);  // the agent's stdin ends: it releases the lease and exits
  to_agent_ = -1;
  // Its client takes up to a call's timeout to release the lease; then it is ended regardless.
  for (int i = 0; pid_ > 0 && i < 300; ++i) {
    if (waitpid(pid_, nullptr, WNOHANG) == pid_) pid_ = -1;
    else std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (pid_ > 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
  pid_ = -1;
  // The reader thread reads to the end of the agent's output, then the file is closed.
  if (from_agent_ && !reader_.joinable()) {
    std::fclose(from_agent_);
    from_agent_ = nullptr;
  }
}

void AgentPageLink::Read() {
  std::string line;
  while (ReadLine(from_agent_, line)) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (line.rfind("E ", 0) == 0) {
      event_ = "data: " + line.substr(2) + "\n\n";
      ++number_;
    } else if (line.rfind("R ", 0) == 0) {
      const json reply = json::parse(line.substr(2), nullptr, false);
      if (reply.is_object()) replies_[reply.value("id", uint64_t{0})] = {reply.value("status", 500), reply["reply"]};
    }
    arrived_.notify_all();
  }
  std::fclose(from_agent_);
  from_agent_ = nullptr;
  std::lock_guard<std::mutex> lock(mutex_);
  alive_ = false;
  arrived_.notify_all();
}

json AgentPageLink::Request(json request, int& status) {
  uint64_t id;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    id = ++next_request_;
  }
  request["id"] = id;
  {
    std::lock_guard<std::mutex> lock(write_mutex_);
    if (to_agent_ < 0 || !WriteAll(to_agent_, request.dump() + "\n")) {
      return Unavailable(status, "this page's DDS client has exited");
    }
  }
  std::unique_lock<std::mutex> lock(mutex_);
  arrived_.wait_for(lock, kReplyTimeout, [&] { return replies_.count(id) || !alive_; });
  const auto it = replies_.find(id);
  if (it == replies_.end()) return Unavailable(status, "no answer from this page's DDS client");
  status = it->second.first;
  json reply = std::move(it->second.second);
  replies_.erase(it);
  return reply;
}

json AgentPageLink::Command(const std::string& name, const std::string& body, int& status) {
  return Request({{"kind", "call"}, {"name", name}, {"body", body}}, status);
}

json AgentPageLink::Skills(int& status) { return Request({{"kind", "skills"}}, status); }

bool AgentPageLink::alive() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return alive_;
}

std::string AgentPageLink::NextEvent(uint64_t after, uint64_t& seen, std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!arrived_.wait_for(lock, timeout, [&] { return !alive_ || number_ > after; }) || !alive_) return "";
  seen = number_;
  return event_;
}

int RunPageAgent(const Client::Options& options) {
  std::unique_ptr<LocalPageLink> link;
  try {
    link = std::make_unique<LocalPageLink>(options);
  } catch (const std::exception& e) {
    std::string why = e.what();
    for (char& c : why) c = c == '\n' ? ' ' : c;
    std::cout << "X " << why << std::endl;
    return 1;
  }
  std::mutex out_mutex;
  const auto send = [&out_mutex](const std::string& line) {
    std::lock_guard<std::mutex> lock(out_mutex);
    std::cout << line << '\n' << std::flush;
  };
  send("I " + link->id());
  std::atomic<bool> running{true};
  std::thread events([&] {
    uint64_t seen = 0;
    while (running) {
      const std::string event = link->NextEvent(seen, seen, std::chrono::milliseconds(500));
      // "data: {...}\n\n" -> "E {...}"
      if (event.size() > 8) send("E " + event.substr(6, event.size() - 8));
    }
  });
  std::string line;
  while (std::getline(std::cin, line)) {
    const json request = json::parse(line, nullptr, false);
    if (!request.is_object()) continue;
    int status = 200;
    const json reply = request.value("kind", "") == "skills"
                           ? link->Skills(status)
                           : link->Command(request.value("name", ""), request.value("body", ""), status);
    send("R " + json{{"id", request.value("id", uint64_t{0})}, {"status", status}, {"reply", reply}}.dump());
  }
  running = false;
  events.join();
  return 0;
}

}  // namespace flsd::web
