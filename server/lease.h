#pragma once
// The control lease: one client at a time may move the robot. The holder keeps it with motion
// requests and renew_control (the client's heartbeat); after `timeout` seconds without either it
// lapses. Time is passed in, so tests drive it without sleeping.

#include <string>

namespace flsd {

class ControlLease {
 public:
  explicit ControlLease(double timeout) : timeout_(timeout) {}

  // Grants the lease to `client` if it is free (or lapsed) or already theirs, renewing it.
  // Returns false when another client holds it.
  bool Acquire(const std::string& client, double now);

  // Renews the lease if `client` holds it; returns whether it does.
  bool Renew(const std::string& client, double now);

  // Gives the lease up if `client` holds it; returns whether it did.
  bool Release(const std::string& client);

  // Drops a lease whose holder has been silent too long; returns true once, when it lapses.
  bool Expire(double now);

  bool held() const { return !holder_.empty(); }
  const std::string& holder() const { return holder_; }
  double timeout() const { return timeout_; }

 private:
  double timeout_;
  std::string holder_;
  double last_renewal_ = 0.0;
};

}  // namespace flsd
