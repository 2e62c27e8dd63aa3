#pragma once
// What a page's session talks to skilld through: its own DDS client, the state stream from it,
// and the page's calls made with its lease. LocalPageLink keeps the client in skillweb's process;
// AgentPageLink (page_agent.h) in a child process of its own, because Cyclone 0.10 keeps one DDS
// Security configuration per process: two pages with two identities need two processes.

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "client/client.h"
#include "client/web/state_feed.h"

namespace flsd::web {

class PageLink {
 public:
  virtual ~PageLink() = default;
  // The client's id, which skilld's lease and audit name: with DDS Security, its identity.
  virtual const std::string& id() const = 0;
  // A call of the page, by name, with its JSON body: the reply as JSON, "audit" saying the result,
  // and the HTTP status (400 bad arguments, 404 not a call the page makes).
  virtual nlohmann::json Command(const std::string& name, const std::string& body, int& status) = 0;
  // The library's skills as JSON, or the refusal (status 503).
  virtual nlohmann::json Skills(int& status) = 0;
  // As StateFeed::Next: the first state event after number `after`, "" after `timeout`.
  virtual std::string NextEvent(uint64_t after, uint64_t& seen, std::chrono::milliseconds timeout) = 0;
  // False once the client is gone for good (a page agent that died): the page's streams end.
  virtual bool alive() const { return true; }
};

class LocalPageLink : public PageLink {
 public:
  explicit LocalPageLink(const Client::Options& options) : client_(options), feed_(client_) {}
  const std::string& id() const override { return client_.id(); }
  nlohmann::json Command(const std::string& name, const std::string& body, int& status) override;
  nlohmann::json Skills(int& status) override;
  std::string NextEvent(uint64_t after, uint64_t& seen, std::chrono::milliseconds timeout) override {
    return feed_.Next(after, seen, timeout);
  }

 private:
  Client client_;
  StateFeed feed_;
};

}  // namespace flsd::web
