#include "fuzz/soak_client.h"

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

#include "fuzz/random_requests.h"
#include "fuzz/reply_oracle.h"

namespace flsd::fuzz {
namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kReplyTimeout = std::chrono::seconds(2);
constexpr auto kStateTimeout = std::chrono::milliseconds(1000);
constexpr int kExamples = 5;

std::string Describe(const RawRequest& r) {
  return "'" + r.call.substr(0, 40) + "' from '" + r.client_id.substr(0, 20) + "' (id " + std::to_string(r.request_id) +
         ")";
}

class Tally {
 public:
  void Wrong(const std::string& what) {
    ++wrong_;
    if (static_cast<int>(examples_.size()) < kExamples) examples_.push_back(what);
  }
  void Dropped(const std::string& what) {
    ++dropped_;
    if (static_cast<int>(dropped_examples_.size()) < kExamples) dropped_examples_.push_back(what);
  }
  void Answered(flsd_msgs_ReplyStatus s) { ++statuses_[dds::StatusName(s)]; }
  void StateChecked() { ++state_checks_; }
  void DampLatency(double ms) { damp_ms_.push_back(ms); }

  nlohmann::json Json(int64_t requests, int64_t late, const RawState& last) const {
    int64_t answered = 0;
    for (const auto& [name, n] : statuses_) answered += n;
    return {{"requests", requests}, {"answered", answered}, {"dropped", dropped_},
            {"dropped_examples", dropped_examples_}, {"late", late}, {"wrong", wrong_},
            {"wrong_examples", examples_}, {"statuses", statuses_}, {"state_checks", state_checks_}, {"damp_latency_ms", damp_ms_},
            {"server_requests_dropped", last.requests_dropped}, {"server_deadline_misses", last.deadline_misses}};
  }

 private:
  int64_t wrong_ = 0, dropped_ = 0, state_checks_ = 0;
  std::vector<std::string> examples_, dropped_examples_;
  std::map<std::string, int64_t> statuses_;
  std::vector<double> damp_ms_;
};

// Three of four requests from an id skilld accepts.
std::vector<std::string> ClientIds(const SoakClientOptions& o, const std::string& identity) {
  const std::string over_long(70, 'c');
  if (o.security.enabled) return {identity, identity, identity, identity, identity, identity, o.name + "-impostor", over_long};
  const std::string a = o.name + "-a", b = o.name + "-b", c = o.name + "-c";
  return {a, b, c, a, b, c, "", over_long};
}

// What the state topic must show after an `ok` reply to `r` (sent at `sent_ns`, wall clock), if
// the call is one whose effect it shows; checks it and records the damp latency.
void CheckState(RawClient& raw, const RawRequest& r, int64_t sent_ns, bool was_damped, Tally& tally) {
  if (r.call == "damp") {
    const std::optional<RawState> damped = raw.WaitForState(
        [&](const RawState& s) { return s.mode == flsd_msgs_MODE_DAMP && s.published_ns >= sent_ns; }, kStateTimeout);
    if (!damped) return tally.Wrong(Describe(r) + ": ok, but the state topic showed no damped robot within 1 s");
    if (!was_damped) tally.DampLatency(static_cast<double>(damped->published_ns - sent_ns) * 1e-6);
  } else if (r.call == "acquire_control") {
    if (!raw.WaitForState([&](const RawState& s) { return s.controller == r.client_id; }, kStateTimeout)) {
      return tally.Wrong(Describe(r) + ": ok, but the state topic did not name it the controller within 1 s");
    }
  } else if (r.call == "release_control") {
    if (!raw.WaitForState([&](const RawState& s) { return s.controller != r.client_id; }, kStateTimeout)) {
      return tally.Wrong(Describe(r) + ": ok, but the state topic still named it the controller after 1 s");
    }
  } else {
    return;
  }
  tally.StateChecked();
}

}  // namespace

nlohmann::json RunSoakClient(const SoakClientOptions& o) {
  RawClient raw(o.domain_id, o.partition, o.security, /*state_depth=*/64);
  if (!raw.WaitForServer(std::chrono::seconds(30))) throw std::runtime_error("no answer from skilld within 30 s");
  const std::string identity = o.security.enabled ? raw.identity() : "";
  const std::vector<std::string> ids = ClientIds(o, identity);
  RandomRequests requests(o.seed, ids, o.heavy_maps);
  ServerFacts facts(o.lease_timeout, o.max_duration);
  facts.can_reset = o.can_reset;
  facts.identity = identity;
  ReplyOracle oracle(facts);
  Tally tally;
  RawState last;
  int64_t sent_count = 0;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / o.rate_hz));
  const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.seconds));
  // The first request asks how many skills there are, for the oracle; a damp is followed by its
  // presser's clear_stop, so that the next damp finds the robot undamped more often.
  std::optional<RawRequest> follow_up = requests.Plain(ids.front(), "list_skills");
  // Paced at rate_hz; after a stall (a reply that never came) it goes on from now, without a burst.
  for (auto next = Clock::now(); Clock::now() < until; next = std::max(next + period, Clock::now())) {
    std::this_thread::sleep_until(next);
    const RawRequest r = follow_up ? *follow_up : requests.Next();
    follow_up.reset();
    if (r.call == "damp") follow_up = requests.Plain(r.client_id, "clear_stop");
    if (std::optional<RawState> s = raw.TakeLatestState()) last = std::move(*s);
    const auto sent = Clock::now();
    const int64_t sent_ns = dds_time();
    const Expectation expected = oracle.Expect(r, sent, sent_ns);
    raw.Send(r);
    ++sent_count;
    // A repeated id may bring the late reply to a dropped request with those ids, which this one's
    // expectation need not fit: counted late, not wrong (a wrong reply to this one then shows as dropped).
    const auto fits = [&expected](const RawReply& reply) { return expected.allowed.Has(reply.status); };
    const std::optional<RawReply> reply = raw.Await(r.client_id, r.request_id, kReplyTimeout, fits);
    oracle.Learn(r, expected, sent, reply);
    if (!reply) {
      tally.Dropped(Describe(r) + ": no reply within 2 s");
      continue;
    }
    tally.Answered(reply->status);
    const std::string got = std::string(dds::StatusName(reply->status)) + ": " + reply->message.substr(0, 200);
    if (const std::string broken = ContractViolation(*reply); !broken.empty()) {
      tally.Wrong(Describe(r) + ": " + broken);
    } else if (!expected.allowed.Has(reply->status)) {
      tally.Wrong(Describe(r) + ": got " + got + "; expected " + expected.allowed.Describe() + " (" + expected.rule + ")");
    } else if (reply->status == flsd_msgs_STATUS_OK && expected.reaches_handler) {
      CheckState(raw, r, sent_ns, last.mode == flsd_msgs_MODE_DAMP, tally);
    }
  }
  if (std::optional<RawState> s = raw.TakeLatestState()) last = std::move(*s);
  return tally.Json(sent_count, raw.late_replies(), last);
}

}  // namespace flsd::fuzz
