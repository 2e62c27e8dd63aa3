#include "client/web/rate_limiter.h"

#include <algorithm>
#include <iterator>

namespace flsd::web {

double RateLimiter::Refilled(const Bucket& bucket, Clock::time_point now) const {
  const double earned = std::chrono::duration<double>(now - bucket.updated) / interval_;
  return std::min<double>(burst_, bucket.tokens + earned);
}

bool RateLimiter::Allow(const std::string& key, Clock::time_point now) {
  std::lock_guard<std::mutex> lock(mutex_);
  // Full buckets say nothing a new one would not: drop them, so many keys cannot grow the map.
  if (buckets_.size() > 4096) {
    for (auto it = buckets_.begin(); it != buckets_.end();) {
      it = Refilled(it->second, now) >= burst_ ? buckets_.erase(it) : std::next(it);
    }
  }
  const auto [it, added] = buckets_.try_emplace(key, Bucket{static_cast<double>(burst_), now});
  Bucket& bucket = it->second;
  bucket.tokens = Refilled(bucket, now);
  bucket.updated = now;
  if (bucket.tokens < 1.0) return false;
  bucket.tokens -= 1.0;
  return true;
}

}  // namespace flsd::web
