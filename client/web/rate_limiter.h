#pragma once
// A token bucket per key (a session, a remote address): `burst` requests at once, then one per
// `interval`. Time is passed in, so that a test can drive it; the callers pass the clock's now.

#include <chrono>
#include <map>
#include <mutex>
#include <string>

namespace flsd::web {

class RateLimiter {
 public:
  using Clock = std::chrono::steady_clock;

  RateLimiter(int burst, Clock::duration interval) : burst_(burst), interval_(interval) {}

  // Whether `key` may make one more request at `now`; if so, it is counted.
  bool Allow(const std::string& key, Clock::time_point now = Clock::now());

 private:
  struct Bucket {
    double tokens;
    Clock::time_point updated;
  };
  double Refilled(const Bucket& bucket, Clock::time_point now) const;

  const int burst_;
  const Clock::duration interval_;
  std::mutex mutex_;
  std::map<std::string, Bucket> buckets_;
};

}  // namespace flsd::web
