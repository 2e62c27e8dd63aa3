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
// Closing the agent's stdin ends it; its client releases the lease on the way out.

#include <sys/types.h>

#include <condition_variable>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "client/web/page_link.h"

namespace flsd::web {

struct AgentOptions {
  std::string program;  // skillweb itself
  int domain_id = 0;
  std::string partition;
  std::string security_file;  // an identity's security.yaml
  bool read_only = false;
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
  nlohmann::json Request(nlohmann::json request, int& status);
  void Read();
  void Stop();

  pid_t pid_ = -1;
  int to_agent_ = -1;
  FILE* from_agent_ = nullptr;
  std::string id_;
  std::mutex write_mutex_;
  mutable std::mutex mutex_;  // what the reader thread fills in
  std::condition_variable arrived_;
  bool alive_ = true;
  std::string event_;
  uint64_t number_ = 0, next_request_ = 0;
  std::map<uint64_t, std::pair<int, nlohmann::json>> replies_;  // by request id: status, reply
  std::thread reader_;
};

// The agent's side, `skillweb --page-agent`: serves one page's client until stdin closes.
int RunPageAgent(const Client::Options& options);

}  // namespace flsd::web
