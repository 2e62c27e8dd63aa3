#include "fuzz/reply_oracle.h"

#include <cmath>

#include "api/calls.h"
#include "fuzz/random_requests.h"

namespace flsd::fuzz {
namespace {

constexpr std::size_t kMaxClientIdLength = 63;  // docs/serving.md: "empty or over-long client ids"
// A holder is sure to hold its lease within this share of the timeout after a request that
// renewed it: the next request, however late DDS delivers it, is not that late.
constexpr double kSureLeaseShare = 0.3;

bool ValidDuration(double d, double max) { return std::isfinite(d) && d > 0.0 && d <= max; }

template <std::size_t N>
bool AllFinite(const std::array<double, N>& values) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

}  // namespace

std::string ContractViolation(const RawReply& reply) {
  if (reply.status < flsd_msgs_STATUS_OK || reply.status > flsd_msgs_STATUS_INTERNAL) {
    return "status " + std::to_string(reply.status) + " is not in the IDL";
  }
  if (reply.status == flsd_msgs_STATUS_INTERNAL) return "internal error: " + reply.message;
  if (reply.status != flsd_msgs_STATUS_OK && reply.message.empty()) return "a refusal without a reason";
  return "";
}

std::string StatusSet::Describe() const {
  std::string text;
  for (int s = flsd_msgs_STATUS_OK; s <= flsd_msgs_STATUS_INTERNAL; ++s) {
    if (!Has(static_cast<flsd_msgs_ReplyStatus>(s))) continue;
    text += (text.empty() ? "" : ", ") + std::string(dds::StatusName(static_cast<flsd_msgs_ReplyStatus>(s)));
  }
  return "{" + text + "}";
}

std::optional<bool> ReplyOracle::Holds(const std::string& client_id, Clock::time_point now) const {
  const auto it = leases_.find(client_id);
  if (it == leases_.end()) return false;
  const Lease& lease = it->second;
  if (lease.held != true) return lease.held;
  if (now - lease.renewed < std::chrono::duration<double>(kSureLeaseShare * facts_.lease_timeout)) return true;
  return std::nullopt;
}

Expectation ReplyOracle::Expect(const RawRequest& r, Clock::time_point sent, int64_t sent_wall_ns) {
  Expectation e;
  e.reaches_handler = false;
  if (!facts_.identity.empty() && r.client_id != facts_.identity) {
    e.allowed = {flsd_msgs_STATUS_INVALID_ARGUMENT};
    e.rule = "with DDS Security a client_id other than the writer's identity is refused";
    return e;
  }
  if (r.client_id.empty() || r.client_id.size() > kMaxClientIdLength) {
    e.allowed = {flsd_msgs_STATUS_INVALID_ARGUMENT};
    e.rule = "client_id must have 1 to 63 characters";
    return e;
  }
  // The server remembers the highest id of a client from its first request on, 0 included.
  const auto [seen, first] = highest_id_.try_emplace(r.client_id, r.request_id);
  const bool duplicate = !first && r.request_id <= seen->second;
  seen->second = std::max(seen->second, r.request_id);
  if (duplicate) {
    e.allowed = {flsd_msgs_STATUS_DUPLICATE};
    e.rule = "request_id not above the client's last";
    return e;
  }
  if (r.deadline_ns < 0) {
    e.allowed = {flsd_msgs_STATUS_INVALID_ARGUMENT};
    e.rule = "a negative deadline is refused";
    return e;
  }
  if (r.deadline_ns > 0 && r.deadline_ns < sent_wall_ns) {
    e.allowed = {flsd_msgs_STATUS_DEADLINE_EXCEEDED};
    e.rule = "sent after its deadline";
    return e;
  }
  e = ExpectCall(r, Holds(r.client_id, sent));
  // A deadline still ahead may pass on the way.
  if (r.deadline_ns > 0) e.allowed.Add(flsd_msgs_STATUS_DEADLINE_EXCEEDED);
  return e;
}

Expectation ReplyOracle::ExpectCall(const RawRequest& r, std::optional<bool> holds) const {
  Expectation e;
  const std::optional<Call> call = FindCall(r.call);
  if (!call) {
    e.allowed = {flsd_msgs_STATUS_UNKNOWN_CALL};
    e.rule = "not a call of the IDL";
    return e;
  }
  switch (*call) {
    case Call::kListSkills:
    case Call::kStatus:
    case Call::kDamp:  // the emergency stop: anyone, any time
      e.allowed = {flsd_msgs_STATUS_OK};
      e.rule = "always answered ok";
      return e;
    case Call::kClearStop:
      e.allowed = {flsd_msgs_STATUS_OK, flsd_msgs_STATUS_SAFETY_STOP};
      e.rule = "cleared, or held for its presser";
      return e;
    case Call::kAcquireControl:
      e.allowed = {flsd_msgs_STATUS_OK};
      if (holds != true) e.allowed.Add(flsd_msgs_STATUS_NOT_IN_CONTROL);
      e.rule = holds == true ? "the holder acquires again" : "granted unless another client holds it";
      return e;
    default:
      break;
  }
  const bool lease_call = *call == Call::kRenewControl || *call == Call::kReleaseControl;
  if (holds != false) e.allowed = lease_call ? StatusSet{flsd_msgs_STATUS_OK} : ExpectMotion(r);
  if (holds != true) e.allowed.Add(flsd_msgs_STATUS_NOT_IN_CONTROL);
  e.rule = holds == true ? "this client holds the lease" : holds == false ? "this client does not hold the lease"
                                                                          : "this client may have lost the lease";
  return e;
}

StatusSet ReplyOracle::ExpectMotion(const RawRequest& r) const {
  using S = StatusSet;
  const StatusSet invalid = {flsd_msgs_STATUS_INVALID_ARGUMENT};
  switch (*FindCall(r.call)) {
    case Call::kExecuteSkill:
    {
      if (!ValidDuration(r.duration, facts_.max_duration)) return invalid;
      const bool known = facts_.num_skills >= 0;
      if (known && (r.skill < 0 || r.skill >= facts_.num_skills)) return invalid;
      // A skill that fell in the library's evaluation is not available.
      S allowed = {flsd_msgs_STATUS_OK, flsd_msgs_STATUS_NOT_AVAILABLE, flsd_msgs_STATUS_SAFETY_STOP};
      if (!known) allowed.Add(flsd_msgs_STATUS_INVALID_ARGUMENT);
      return allowed;
    }
    case Call::kTrackVelocity:
      if (!AllFinite(r.velocity) || !ValidDuration(r.duration, facts_.max_duration)) return invalid;
      return S{flsd_msgs_STATUS_OK, flsd_msgs_STATUS_SAFETY_STOP};
    case Call::kNavigate: {
      const MapCase* map = RandomRequests::FindMap(r.map_yaml);
      const bool oversize = r.map_yaml.size() > 64 * 1024;
      if (!AllFinite(r.goal) || oversize || (r.duration != 0.0 && !ValidDuration(r.duration, facts_.max_duration))) {
        return invalid;
      }
      // The map is read after the safety check.
      S allowed = {flsd_msgs_STATUS_SAFETY_STOP};
      allowed.Add(map == nullptr || map->valid ? flsd_msgs_STATUS_OK : flsd_msgs_STATUS_INVALID_ARGUMENT);
      return allowed;
    }
    case Call::kStop:
      return S{flsd_msgs_STATUS_OK};
    case Call::kStand:
      return S{flsd_msgs_STATUS_OK, flsd_msgs_STATUS_SAFETY_STOP};
    case Call::kReset:
      return facts_.can_reset ? S{flsd_msgs_STATUS_OK, flsd_msgs_STATUS_SAFETY_STOP} : S{flsd_msgs_STATUS_NOT_AVAILABLE};
    default:
      return S{};
  }
}

void ReplyOracle::Learn(const RawRequest& r, const Expectation& e, Clock::time_point sent,
                        const std::optional<RawReply>& reply) {
  if (!e.reaches_handler) return;
  Lease& lease = leases_[r.client_id];
  if (!reply) {
    lease.held.reset();
    return;
  }
  if (reply->status == flsd_msgs_STATUS_DEADLINE_EXCEEDED) return;  // refused before the lease was touched
  const std::optional<Call> call = FindCall(r.call);
  if (call == Call::kListSkills && reply->status == flsd_msgs_STATUS_OK) facts_.num_skills = static_cast<int>(reply->skills);
  if (call == Call::kReleaseControl || reply->status == flsd_msgs_STATUS_NOT_IN_CONTROL) {
    lease.held = false;
  } else if (call == Call::kAcquireControl || call == Call::kRenewControl || (call && Spec(*call).needs_control)) {
    lease.held = true;  // granted, renewed, or past the lease check
    lease.renewed = sent;
  } else if (const std::optional<bool> held = Holds(r.client_id, sent); held != false) {
    // Any other call renews a lease that is surely held, and says nothing of one that may have lapsed.
    lease.held = held;
    lease.renewed = sent;
  }
}

}  // namespace flsd::fuzz
