#pragma once
// The state topic as server-sent events: one thread follows the client's state samples and keeps
// the newest as an event; every open page waits for the next one. A page that falls behind skips
// to the newest, as the topic itself does (best effort, newest only), and never slows the others.

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "client/client.h"

namespace flsd::web {

class StateFeed {
 public:
  explicit StateFeed(const Client& client);
  ~StateFeed();
  StateFeed(const StateFeed&) = delete;
  StateFeed& operator=(const StateFeed&) = delete;

  // The first event after number `after` ("data: {...}\n\n"), and its number in `seen`;
  // "" after `timeout`, or once the feed stops.
  std::string Next(uint64_t after, uint64_t& seen, std::chrono::milliseconds timeout) const;

 private:
  void Follow();

  const Client& client_;
  mutable std::mutex mutex_;
  mutable std::condition_variable arrived_;
  std::string event_;
  uint64_t number_ = 0;
  bool running_ = true;
  std::thread follower_;
};

}  // namespace flsd::web
