#include "server/lease.h"

namespace flsd {

bool ControlLease::Acquire(const std::string& client, double now) {
  Expire(now);
  if (held() && holder_ != client) return false;
  holder_ = client;
  last_renewal_ = now;
  return true;
}

bool ControlLease::Renew(const std::string& client, double now) {
  Expire(now);
  if (!held() || holder_ != client) return false;
  last_renewal_ = now;
  return true;
}

bool ControlLease::Release(const std::string& client) {
  if (!held() || holder_ != client) return false;
  holder_.clear();
  return true;
}

bool ControlLease::Expire(double now) {
  if (!held() || now - last_renewal_ <= timeout_) return false;
  holder_.clear();
  return true;
}

}  // namespace flsd
