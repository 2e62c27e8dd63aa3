#include "fuzz/raw_client.h"

#include <algorithm>
#include <thread>

namespace flsd::fuzz {
namespace {

std::string Text(const char* s) { return s != nullptr ? s : ""; }

}  // namespace

RawClient::RawClient(int domain_id, const std::string& partition, const dds::SecurityConfig& security,
                     int state_depth)
    : domain_(domain_id, partition, security),
      requests_(domain_, flsd_msgs_Request_desc, dds::kRequestTopic, dds::kRequestQos),
      replies_(domain_, flsd_msgs_Reply_desc, dds::kReplyTopic, dds::kReplyQos),
      states_(domain_, flsd_msgs_RobotState_desc, dds::kStateTopic, dds::EndpointQos::BestEffort(state_depth)) {}

bool RawClient::WaitForServer(std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  RawRequest probe;
  probe.client_id = "raw-probe";
  probe.call = "status";
  while (std::chrono::steady_clock::now() < until) {
    ++probe.request_id;
    if (requests_.matched_readers() > 0 && replies_.matched_writers() > 0 &&
        Call(probe, std::chrono::milliseconds(200))) {
      unanswered_.clear();  // probes sent before discovery settled: no late replies of the caller's
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

void RawClient::Send(const RawRequest& r) {
  outstanding_[{r.client_id, r.request_id}].clear();
  flsd_msgs_Request m{};
  m.header.client_id = const_cast<char*>(r.client_id.c_str());
  m.header.request_id = r.request_id;
  m.header.deadline_ns = r.deadline_ns;
  m.call = const_cast<char*>(r.call.c_str());
  m.skill = r.skill;
  m.duration = r.duration;
  std::copy(r.velocity.begin(), r.velocity.end(), m.velocity);
  std::copy(r.goal.begin(), r.goal.end(), m.goal);
  m.map_yaml = const_cast<char*>(r.map_yaml.c_str());
  requests_.Write(m);
}

void RawClient::TakeReplies() {
  replies_.Take([&](const flsd_msgs_Reply& m, const dds_sample_info_t& info) {
    const Key key{Text(m.header.client_id), m.header.request_id};
    const auto it = outstanding_.find(key);
    if (it == outstanding_.end()) {
      CountLate(key);  // if late; else another client's, or one already awaited
      return;
    }
    RawReply& r = it->second.emplace_back();
    r.status = m.status;
    r.message = Text(m.message);
    r.safety_report = Text(m.safety_report);
    r.skills = m.skills._length;
    r.published_ns = info.source_timestamp;
  }, 1 << 20);
}

bool RawClient::CountLate(const Key& key) {
  const auto it = unanswered_.find(key);
  if (it == unanswered_.end()) return false;
  ++late_replies_;
  if (--it->second == 0) unanswered_.erase(it);
  return true;
}

std::optional<RawReply> RawClient::Await(const std::string& client_id, uint64_t request_id,
                                         std::chrono::milliseconds timeout,
                                         const std::function<bool(const RawReply&)>& belongs) {
  const Key key{client_id, request_id};
  const auto it = outstanding_.find(key);
  if (it == outstanding_.end()) return std::nullopt;
  const auto until = std::chrono::steady_clock::now() + timeout;
  std::optional<RawReply> reply;
  for (;;) {
    TakeReplies();
    for (std::deque<RawReply>& came = it->second; !reply && !came.empty(); came.pop_front()) {
      const bool late = belongs && !belongs(came.front()) && CountLate(key);
      if (!late) reply = std::move(came.front());
    }
    const auto now = std::chrono::steady_clock::now();
    if (reply || now >= until) break;
    replies_.Wait(until - now);
  }
  // A reply beside this one answers an earlier request with the same ids.
  for (std::size_t i = 0; i < it->second.size(); ++i) CountLate(key);
  outstanding_.erase(it);
  if (!reply) ++unanswered_[key];
  return reply;
}

std::optional<RawState> RawClient::TakeLatestState() {
  std::optional<RawState> latest;
  TakeStates([&](RawState&& s) { latest = std::move(s); });
  return latest;
}

RawState RawClient::Own(const flsd_msgs_RobotState& m, const dds_sample_info_t& info) {
  RawState s;
  s.received = std::chrono::steady_clock::now();
  s.published_ns = info.source_timestamp;
  s.tick = m.tick;
  s.time = m.time;
  s.mode = m.mode;
  s.faults = m.faults;
  s.fault_message = Text(m.fault_message);
  s.controller = Text(m.controller);
  s.task_client_id = Text(m.task.client_id);
  s.task_call = Text(m.task.call);
  s.task_message = Text(m.task.message);
  s.task_request_id = m.task.request_id;
  s.task_state = m.task.state;
  s.deadline_misses = m.deadline_misses;
  s.requests_dropped = m.requests_dropped;
  return s;
}

}  // namespace flsd::fuzz
