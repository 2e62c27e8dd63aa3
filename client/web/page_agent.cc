#include "client/web/page_agent.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <vector>

namespace flsd::web {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

// How soon the reader thread sees that it is to stop.
constexpr std::chrono::seconds kReaderPoll{1};

// Writes `text` to the non-blocking `fd` whole, unless that is not done by `until`: an agent that
// stops reading must not hold skillweb's request threads in a write.
bool WriteAll(int fd, const std::string& text, Clock::time_point until) {
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n == 0 || errno != EAGAIN) return false;
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(until - Clock::now());
    pollfd ready{fd, POLLOUT, 0};
    if (left.count() <= 0) return false;
    const int polled = poll(&ready, 1, static_cast<int>(left.count()));
    if (polled == 0 || (polled < 0 && errno != EINTR)) return false;
  }
  return true;
}

json Refused(int& status, int code, const std::string& why) {
  status = code;
  return json{{"ok", false}, {"status", "refused"}, {"message", why}, {"audit", "refused: " + why}};
}

json Unavailable(int& status, const std::string& why) { return Refused(status, 503, why); }

constexpr const char* kGone = "this page's DDS client has exited or stopped taking requests";

json OutOfProtocol(int& status, const std::string& why) {
  return Refused(status, 502, "this page's DDS client answered out of protocol: " + why);
}

// Why an agent's reply, past its id, lacks an HTTP status or a reply (an object, or the skills'
// list); "" if it has both.
std::string ReplyShapeError(const json& r) {
  const auto status = r.find("status"), reply = r.find("reply");
  if (status == r.end() || !status->is_number_integer() || *status < 100 || *status > 599) return "no HTTP status";
  if (reply == r.end() || !(reply->is_object() || reply->is_array())) return "no reply object or list";
  return "";
}

}  // namespace

AgentPageLink::AgentPageLink(const AgentOptions& options) : reply_timeout_(options.reply_timeout) {
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
  from_agent_ = out[0];
  fcntl(to_agent_, F_SETFL, O_NONBLOCK);
  if (pid_ < 0) {
    Stop();
    throw std::runtime_error("page agent: cannot start " + options.program);
  }
  // An agent that stalls before or within its first line fails like one that says nothing.
  std::string line;
  const LineRead first = ReadLine(line, Clock::now() + options.start_timeout);
  if (first != LineRead::kLine || line.rfind("I ", 0) != 0) {
    Stop();
    throw std::runtime_error(line.rfind("X ", 0) == 0 ? line.substr(2) : "its DDS client did not start");
  }
  id_ = line.substr(2);
  reader_ = std::thread([this] { Read(); });
}

AgentPageLink::~AgentPageLink() {
  Stop();
  stopping_ = true;  // the agent is gone, but a process it left may hold its output open
  if (reader_.joinable()) reader_.join();
  if (from_agent_ >= 0) close(from_agent_);
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
  // The reader thread reads to the end of the agent's output; without one, it is closed here.
  if (from_agent_ >= 0 && !reader_.joinable()) {
    close(from_agent_);
    from_agent_ = -1;
  }
}

AgentPageLink::LineRead AgentPageLink::ReadLine(std::string& line, Clock::time_point until) {
  for (;;) {
    if (const auto newline = unread_.find('\n'); newline != std::string::npos) {
      line = unread_.substr(0, newline);
      unread_.erase(0, newline + 1);
      return LineRead::kLine;
    }
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(until - Clock::now());
    pollfd ready{from_agent_, POLLIN, 0};
    const int polled = left.count() > 0 ? poll(&ready, 1, static_cast<int>(left.count())) : 0;
    if (polled < 0 && errno == EINTR) continue;
    if (polled == 0) return LineRead::kTimeout;
    char bytes[4096];
    const ssize_t n = polled < 0 ? -1 : ::read(from_agent_, bytes, sizeof bytes);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return LineRead::kEnd;
    unread_.append(bytes, static_cast<std::size_t>(n));
  }
}

void AgentPageLink::Read() {
  std::string line;
  while (!stopping_) {
    const LineRead next = ReadLine(line, Clock::now() + kReaderPoll);
    if (next == LineRead::kEnd) break;
    if (next == LineRead::kTimeout) continue;  // no skilld, or no call: an agent may say nothing for long
    if (line.rfind("E ", 0) == 0) {
      std::lock_guard<std::mutex> lock(mutex_);
      event_ = "data: " + line.substr(2) + "\n\n";
      ++number_;
      arrived_.notify_all();
    } else if (line.rfind("R ", 0) == 0) {
      TakeReply(line.substr(2));
    }
  }
  std::lock_guard<std::mutex> lock(mutex_);
  alive_ = false;
  arrived_.notify_all();
}

void AgentPageLink::TakeReply(const std::string& text) {
  const json r = json::parse(text, nullptr, false);
  const auto id = r.find("id");
  if (id == r.end() || !id->is_number_unsigned()) {
    std::fprintf(stderr, "skillweb: page agent %s: dropped a reply without a request id: %s\n", id_.c_str(),
                 text.substr(0, 200).c_str());
    return;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  const auto waiting = replies_.find(id->get<uint64_t>());
  if (waiting == replies_.end()) {
    // Its request gave up and told the page "no answer": the call may have run all the same.
    std::fprintf(stderr, "skillweb: page agent %s: dropped the late answer to request %s: %s\n", id_.c_str(),
                 id->dump().c_str(), text.substr(0, 200).c_str());
    return;
  }
  if (const std::string error = ReplyShapeError(r); error.empty()) {
    waiting->second.emplace(r.at("status").get<int>(), r.at("reply"));
  } else {
    int status = 0;
    json refusal = OutOfProtocol(status, error);
    waiting->second.emplace(status, std::move(refusal));
  }
  arrived_.notify_all();
}

json AgentPageLink::Request(json request, int& status) {
  const Clock::time_point deadline = Clock::now() + reply_timeout_;  // for the write and the answer
  uint64_t id;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!alive_) return Unavailable(status, kGone);
    id = ++next_request_;
    replies_[id];  // awaited from now on
  }
  request["id"] = id;
  bool sent;
  {
    std::lock_guard<std::mutex> lock(write_mutex_);
    sent = to_agent_ >= 0 && WriteAll(to_agent_, request.dump() + "\n", deadline);
    // Part of a line may be in the pipe: the agent would read it as garbage. An agent that stopped
    // reading is ended; its reader then sees the end, and the page's streams close.
    if (!sent && pid_ > 0) kill(pid_, SIGKILL);
  }
  std::unique_lock<std::mutex> lock(mutex_);
  const auto it = replies_.find(id);
  if (sent) arrived_.wait_until(lock, deadline, [&] { return it->second.has_value() || !alive_; });
  std::optional<std::pair<int, json>> reply = std::move(it->second);
  replies_.erase(it);  // a reply after this is late, and dropped
  if (!sent) return Unavailable(status, kGone);
  if (!reply) return Unavailable(status, "no answer from this page's DDS client");
  status = reply->first;
  return std::move(reply->second);
}

json AgentPageLink::Command(const std::string& name, const std::string& body, int& status) {
  json reply = Request({{"kind", "call"}, {"name", name}, {"body", body}}, status);
  // skillweb audits every command by its reply's "audit".
  const auto audit = reply.find("audit");
  if (audit == reply.end() || !audit->is_string()) return OutOfProtocol(status, "a command's reply without its audit");
  return reply;
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
