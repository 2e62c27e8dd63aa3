#include "client/web/state_feed.h"

#include "client/web/web_json.h"

namespace flsd::web {

StateFeed::StateFeed(const Client& client) : client_(client), follower_([this] { Follow(); }) {}

StateFeed::~StateFeed() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    running_ = false;
  }
  arrived_.notify_all();
  follower_.join();
}

void StateFeed::Follow() {
  uint64_t tick = 0;
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!running_) return;
    }
    const std::optional<StateReport> state = client_.NextState(tick, std::chrono::milliseconds(200));
    if (!state) {
      tick = 0;  // a restarted server counts its ticks from zero again
      continue;
    }
    tick = state->tick;
    nlohmann::json sample = ToJson(*state);
    // When skillweb had the sample, wall clock in ms: the page shows the stream's delay from it.
    sample["received"] = std::chrono::duration<double, std::milli>(std::chrono::system_clock::now().time_since_epoch()).count();
    std::string event = "data: " + sample.dump() + "\n\n";
    {
      std::lock_guard<std::mutex> lock(mutex_);
      event_ = std::move(event);
      ++number_;
    }
    arrived_.notify_all();
  }
}

std::string StateFeed::Next(uint64_t after, uint64_t& seen, std::chrono::milliseconds timeout) const {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!arrived_.wait_for(lock, timeout, [&] { return !running_ || number_ > after; }) || !running_) return "";
  seen = number_;
  return event_;
}

}  // namespace flsd::web
