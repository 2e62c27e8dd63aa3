#pragma once
// What skilld may answer, by its documented contract (idl/flsd_msgs.idl, docs/serving.md): the
// checks any reply must pass, and the statuses one client's request allows, from the request
// itself and from what the client knows of its own control lease. Only the client's own calls
// grant it the lease, and only its own calls or its silence take it away; so, with other clients
// calling at the same time, the oracle still knows whether it holds the lease, except after a
// silence near the lease timeout or an unanswered call, when it allows either answer.

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "fuzz/raw_client.h"

namespace flsd::fuzz {

// Why `reply` breaks the contract whatever was asked (a status outside the IDL's, an internal
// error, a refusal without a reason); empty if it does not.
std::string ContractViolation(const RawReply& reply);

// A set of reply statuses.
class StatusSet {
 public:
  StatusSet() = default;
  StatusSet(std::initializer_list<flsd_msgs_ReplyStatus> statuses) {
    for (flsd_msgs_ReplyStatus s : statuses) Add(s);
  }
  void Add(flsd_msgs_ReplyStatus s) { bits_ |= 1u << s; }
  bool Has(flsd_msgs_ReplyStatus s) const { return s >= 0 && s < 32 && (bits_ >> s & 1u) != 0; }
  std::string Describe() const;  // "{ok, safety stop}"

 private:
  uint32_t bits_ = 0;
};

// The statuses allowed for one request, and the rule that says so.
struct Expectation {
  StatusSet allowed;
  std::string rule;
  bool reaches_handler = true;  // past the header checks: it renews the sender's lease if held
};

struct ServerFacts {
  // skilld's settings, from its config: no default here, where a guess would go stale.
  ServerFacts(double lease_timeout_s, double max_duration_s)
      : lease_timeout(lease_timeout_s), max_duration(max_duration_s) {}

  double lease_timeout;         // s
  double max_duration;          // s
  int num_skills = -1;          // the library's; -1 until a list_skills reply tells
  bool can_reset = true;        // the sim backend can; the real robot cannot
  std::string identity;         // with DDS Security, this participant's: the only client_id accepted
};

class ReplyOracle {
 public:
  using Clock = std::chrono::steady_clock;
  explicit ReplyOracle(ServerFacts facts) : facts_(std::move(facts)) {}

  // Call before sending `r` at `sent` (wall clock `sent_wall_ns`); the ids it has seen decide
  // which request is a duplicate.
  Expectation Expect(const RawRequest& r, Clock::time_point sent, int64_t sent_wall_ns);
  // What the answer to `r` (nullopt: none came) says of the sender's lease and of the server.
  void Learn(const RawRequest& r, const Expectation& e, Clock::time_point sent, const std::optional<RawReply>& reply);
  // Whether `client_id` holds the lease at `now`; nullopt when it cannot be known.
  std::optional<bool> Holds(const std::string& client_id, Clock::time_point now) const;

 private:
  struct Lease {
    std::optional<bool> held = false;
    Clock::time_point renewed;
  };
  Expectation ExpectCall(const RawRequest& r, std::optional<bool> holds) const;
  StatusSet ExpectMotion(const RawRequest& r) const;

  ServerFacts facts_;
  std::map<std::string, uint64_t> highest_id_;
  std::map<std::string, Lease> leases_;
};

}  // namespace flsd::fuzz
