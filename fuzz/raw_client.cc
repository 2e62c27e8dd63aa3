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
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

void RawClient::Send(const RawRequest& r) {
  outstanding_[{r.client_id, r.request_id}].reset();
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
  replies_.Take([&](const flsd_msgs_Reply& m, const dds_sample_info_t&) {
    const auto it = outstanding_.find({Text(m.header.client_id), m.header.request_id});
    if (it == outstanding_.end()) return;  // another client's, or one already awaited
    RawReply& r = it->second.emplace();
    r.status = m.status;
    r.message = Text(m.message);
    r.safety_report = Text(m.safety_report);
    r.skills = m.skills._length;
  }, 1 << 20);
}

std::optional<RawReply> RawClient::Await(const std::string& client_id, uint64_t request_id,
                                         std::chrono::milliseconds timeout) {
  const auto it = outstanding_.find({client_id, request_id});
  if (it == outstanding_.end()) return std::nullopt;
  const auto until = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    TakeReplies();
    const auto now = std::chrono::steady_clock::now();
    if (it->second || now >= until) break;
    replies_.Wait(until - now);
  }
  std::optional<RawReply> reply = std::move(it->second);
  outstanding_.erase(it);
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
