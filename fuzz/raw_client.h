#pragma once
// A client of skilld written from idl/flsd_msgs.idl alone, as an independent one would be: raw
// requests with any header and fields (no flsd::Client: no id discipline, no lease heartbeat),
// replies matched by client and request id, and the state topic. The adversarial tests and the
// soak bench drive the real skilld over real DDS with it.

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "comm/protocol.h"

namespace flsd::fuzz {

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
  uint32_t skills = 0;  // list_skills: how many
  int64_t published_ns = 0;  // the writer's CLOCK_REALTIME timestamp of the reply
};

// What the tests and the soak look at in a state sample, with its strings owned.
struct RawState {
  std::chrono::steady_clock::time_point received;
  int64_t published_ns = 0;  // the writer's CLOCK_REALTIME timestamp of the sample
  uint64_t tick = 0;
  double time = 0.0;  // s, the server's clock
  flsd_msgs_Mode mode = flsd_msgs_MODE_IDLE;
  uint32_t faults = 0;
  std::string fault_message, controller;
  std::string task_client_id, task_call, task_message;
  uint64_t task_request_id = 0;
  flsd_msgs_TaskState task_state = flsd_msgs_TASK_NONE;
  uint64_t deadline_misses = 0, requests_dropped = 0;
};

class RawClient {
 public:
  // With `security`, creating it throws dds::Error if Cyclone refuses the credentials or the
  // permissions do not allow these topics. `state_depth`: state samples kept unread (the topic's
  // newest-only by default; more lets a busy reader see every tick).
  RawClient(int domain_id, const std::string& partition, const dds::SecurityConfig& security = {},
            int state_depth = 1);

  // Until the server's reader and writer are matched with ours and a status call is answered.
  bool WaitForServer(std::chrono::milliseconds timeout);

  // This participant's authenticated identity: with DDS Security, the only client_id skilld accepts from it.
  std::string identity() const { return domain_.identity(); }

  // A reply seen before to the same ids (a request sent again) is forgotten: Await waits for a new one.
  void Send(const RawRequest& r);

  // The reply to (client_id, request_id) of a request sent before, or nullopt after `timeout`.
  // Replies to requests not sent from here, or already awaited, are not kept. A request given up
  // on may still be answered, after another with the same ids was sent: a reply `belongs` refuses
  // is then taken for the late one (counted in late_replies()), and the wait goes on.
  std::optional<RawReply> Await(const std::string& client_id, uint64_t request_id, std::chrono::milliseconds timeout,
                                const std::function<bool(const RawReply&)>& belongs = nullptr);

  std::optional<RawReply> Call(const RawRequest& r, std::chrono::milliseconds timeout = std::chrono::seconds(2)) {
    Send(r);
    return Await(r.client_id, r.request_id, timeout);
  }

  // The first state sample from now on (of those kept unread) for which `done` holds, or
  // nullopt after `timeout`. The samples before it are taken too.
  template <class P>
  std::optional<RawState> WaitForState(P&& done, std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    std::optional<RawState> found;
    while (!found) {
      TakeStates([&](RawState&& s) {
        if (!found && done(s)) found = std::move(s);
      });
      const auto now = std::chrono::steady_clock::now();
      if (found || now >= until) break;
      states_.Wait(until - now);
    }
    return found;
  }

  // Takes every state sample kept unread; the newest of them, if any.
  std::optional<RawState> TakeLatestState();

  // Replies so far to requests Await had given up on (WaitForServer's probes aside).
  int64_t late_replies() {
    TakeReplies();
    return late_replies_;
  }

 private:
  using Key = std::pair<std::string, uint64_t>;
  template <class F>
  void TakeStates(F&& on_state) {
    states_.Take([&](const flsd_msgs_RobotState& m, const dds_sample_info_t& info) { on_state(Own(m, info)); },
                 1 << 20);
  }
  static RawState Own(const flsd_msgs_RobotState& m, const dds_sample_info_t& info);
  void TakeReplies();
  // Whether a request with `key` went unanswered and may be answered still; if so, this reply is
  // counted as its late one.
  bool CountLate(const Key& key);

  dds::Domain domain_;
  dds::Writer<flsd_msgs_Request> requests_;
  dds::Reader<flsd_msgs_Reply> replies_;
  dds::Reader<flsd_msgs_RobotState> states_;
  // Requests sent and not yet awaited, with the replies that came for their ids.
  std::map<Key, std::deque<RawReply>> outstanding_;
  std::map<Key, int> unanswered_;  // requests Await gave up on, by ids, whose replies have not come
  int64_t late_replies_ = 0;
};

}  // namespace flsd::fuzz
