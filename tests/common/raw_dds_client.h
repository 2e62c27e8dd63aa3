#pragma once
// A client of skilld written from idl/flsd_msgs.idl alone, as an independent one would be: raw
// requests with any header and fields (no flsd::Client: no id discipline, no lease heartbeat),
// replies matched by client and request id, and the state topic. For adversarial tests against
// the real skilld over real DDS.

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "comm/protocol.h"
#include "tests/common/skilld_fixture.h"

namespace flsd::testutil {

struct RawRequest {
  std::string client_id;
  uint64_t request_id = 0;
  int64_t deadline_ns = 0;
  std::string call;
  int32_t skill = 0;
  double duration = 0.0;
  std::array<double, 3> velocity{};
  std::array<double, 2> goal{};
  std::string map_yaml;
};

struct RawReply {
  flsd_msgs_ReplyStatus status = flsd_msgs_STATUS_INTERNAL;
  std::string message, safety_report;
};

// What the tests look at in a state sample, with its strings owned.
struct RawState {
  std::chrono::steady_clock::time_point received;
  uint64_t tick = 0;
  flsd_msgs_Mode mode = flsd_msgs_MODE_IDLE;
  uint32_t faults = 0;
  std::string fault_message, controller;
  std::string task_client_id, task_call, task_message;
  uint64_t task_request_id = 0;
  flsd_msgs_TaskState task_state = flsd_msgs_TASK_NONE;
};

class RawClient {
 public:
  // With `security`, creating it throws dds::Error if Cyclone refuses the credentials or the
  // permissions do not allow these topics.
  RawClient(int domain_id, const std::string& partition, const dds::SecurityConfig& security = {})
      : domain_(domain_id, partition, security),
        requests_(domain_, flsd_msgs_Request_desc, dds::kRequestTopic, dds::kRequestQos),
        replies_(domain_, flsd_msgs_Reply_desc, dds::kReplyTopic, dds::kReplyQos),
        states_(domain_, flsd_msgs_RobotState_desc, dds::kStateTopic, dds::kStateQos) {}

  // Until the server's reader and writer are matched with ours and a status call is answered.
  bool WaitForServer(std::chrono::milliseconds timeout) {
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

  // This participant's authenticated identity: with DDS Security, the only client_id skilld accepts from it.
  std::string identity() const { return domain_.identity(); }

  // A reply seen before to the same ids (a request sent again) is forgotten: Await waits for a new one.
  void Send(const RawRequest& r) {
    replies_seen_.erase({r.client_id, r.request_id});
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

  // The reply to (client_id, request_id), or nullopt after `timeout`.
  std::optional<RawReply> Await(const std::string& client_id, uint64_t request_id, std::chrono::milliseconds timeout) {
    const auto key = std::make_pair(client_id, request_id);
    const auto until = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      replies_.Take([&](const flsd_msgs_Reply& m, const dds_sample_info_t&) {
        RawReply& r = replies_seen_[{Own(m.header.client_id), m.header.request_id}];
        r.status = m.status;
        r.message = Own(m.message);
        r.safety_report = Own(m.safety_report);
      }, 1 << 20);
      if (auto it = replies_seen_.find(key); it != replies_seen_.end()) return it->second;
      const auto now = std::chrono::steady_clock::now();
      if (now >= until) return std::nullopt;
      replies_.Wait(until - now);
    }
  }

  std::optional<RawReply> Call(const RawRequest& r, std::chrono::milliseconds timeout = std::chrono::seconds(2)) {
    Send(r);
    return Await(r.client_id, r.request_id, timeout);
  }

  // The first state sample from now on for which `done` holds, or nullopt after `timeout`.
  template <class P>
  std::optional<RawState> WaitForState(P&& done, std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    std::optional<RawState> found;
    while (!found) {
      states_.Take([&](const flsd_msgs_RobotState& m, const dds_sample_info_t&) {
        RawState s;
        s.received = std::chrono::steady_clock::now();
        s.tick = m.tick;
        s.mode = m.mode;
        s.faults = m.faults;
        s.fault_message = Own(m.fault_message);
        s.controller = Own(m.controller);
        s.task_client_id = Own(m.task.client_id);
        s.task_call = Own(m.task.call);
        s.task_message = Own(m.task.message);
        s.task_request_id = m.task.request_id;
        s.task_state = m.task.state;
        if (!found && done(s)) found = std::move(s);
      }, 1 << 20);
      const auto now = std::chrono::steady_clock::now();
      if (found || now >= until) break;
      states_.Wait(until - now);
    }
    return found;
  }

 private:
  static std::string Own(const char* s) { return s != nullptr ? s : ""; }

  dds::Domain domain_;
  dds::Writer<flsd_msgs_Request> requests_;
  dds::Reader<flsd_msgs_Reply> replies_;
  dds::Reader<flsd_msgs_RobotState> states_;
  std::map<std::pair<std::string, uint64_t>, RawReply> replies_seen_;
};

// A real skilld on loopback with a RawClient connected to it.
class RawSkilldFixture : public SkilldFixture {
 protected:
  void SetUp() override {
    SkilldFixture::SetUp();
    StartServer();
    raw_ = std::make_unique<RawClient>(domain_, partition_);
    ASSERT_TRUE(raw_->WaitForServer(std::chrono::seconds(15))) << server_->Log();
  }

  // A request with the next id: ids from the wall clock, as the IDL asks of a client.
  RawRequest Request(const std::string& client, const std::string& call) {
    RawRequest r;
    r.client_id = client;
    r.request_id = ++next_id_;
    r.call = call;
    return r;
  }

  std::unique_ptr<RawClient> raw_;
  uint64_t next_id_ = static_cast<uint64_t>(dds_time());
};

}  // namespace flsd::testutil
