#pragma once
// A page's DDS client in a child process: `skillweb --page-agent` runs a LocalPageLink and speaks
// to skillweb over its stdin and stdout, one line a message. skillweb uses it for logins with DDS
// Security (--pki), since Cyclone 0.10 validates a second identity in one process but its peers
// then refuse it ("Subject name is invalid"): each identity needs a process of its own.
//
//   skillweb -> agent   {"id": N, "kind": "call", "name": ..., "body": ...} or {"id": N, "kind": "skills"}
//   agent -> skillweb   "I <client id>" once ready, or "X <why>" and exit;
//                       then "E <state JSON>" per state event and "R {"id", "status", "reply"}" per request
//
// Closing the agent's stdin ends it; its client releases the lease on the way out. skillweb waits
// for each line with a timeout, refuses a reply of another shape (502), and drops, with a line on
// stderr, a reply that comes after its request gave up.

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "client/web/page_link.h"

namespace flsd::web {

struct AgentOptions {
  std::string program;  // skillweb itself
  int domain_id = 0;
  std::string partition;
  std::string security_file;  // an identity's security.yaml
  bool read_only = false;
  std::chrono::milliseconds start_timeout{20000};  // for its client to start
  std::chrono::milliseconds reply_timeout{30000};  // for the answer to a call
};

class AgentPageLink : public PageLink {
 public:
  // Starts the agent and waits for its client; throws std::runtime_error with the agent's reason.
  explicit AgentPageLink(const AgentOptions& options);
  ~AgentPageLink() override;
  AgentPageLink(const AgentPageLink&) = delete;
  AgentPageLink& operator=(const AgentPageLink&) = delete;

  const std::string& id() const override { return id_; }
  nlohmann::json Command(const std::string& name, const std::string& body, int& status) override;
  nlohmann::json Skills(int& status) override;
  std::string NextEvent(uint64_t after, uint64_t& seen, std::chrono::milliseconds timeout) override;
  bool alive() const override;

 private:
  enum class LineRead { kLine, kEnd, kTimeout };
  // The agent's next line, without its newline, if it comes whole by `until`.
  LineRead ReadLine(std::string& line, std::chrono::steady_clock::time_point until);
  nlohmann::json Request(nlohmann::json request, int& status);
  void Read();
  void TakeReply(const std::string& text);
  void Stop();

  const std::chrono::milliseconds reply_timeout_;
  pid_t pid_ = -1;
  int to_agent_ = -1, from_agent_ = -1;
  std::string unread_;  // what the agent wrote after the last whole line (the reader's)
  std::string id_;
  std::mutex write_mutex_;
  mutable std::mutex mutex_;  // what the reader thread fills in
  std::condition_variable arrived_;
  bool alive_ = true;
  std::atomic<bool> stopping_{false};  // the reader ends even if the agent's output stays open
  std::string event_;
  uint64_t number_ = 0, next_request_ = 0;
  // By request id while its caller waits: status and reply once they came.
  std::map<uint64_t, std::optional<std::pair<int, nlohmann::json>>> replies_;
  std::thread reader_;
};

// The agent's side, `skillweb --page-agent`: serves one page's client until stdin closes.
int RunPageAgent(const Client::Options& options);

}  // namespace flsd::web
