#pragma once
// flsd::Client: calls skilld over DDS and follows its state topic. Calls are synchronous with a
// timeout; while the client holds control, a background thread renews the lease, so a client
// process that dies lets the robot stand within the lease timeout. (A client whose main thread
// hangs keeps renewing: give long motions a duration, which the server enforces.)

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "comm/dds.h"
#include "flsd_msgs.h"

namespace flsd {

struct CallArgs {
  int skill = 0;
  double duration = 0.0;
  std::array<double, 3> velocity{};
  std::array<double, 2> goal{};
  std::string map_yaml;
};

struct CallResult {
  uint64_t request_id = 0;  // the call's: its task on the state topic carries it
  bool answered = false;  // false: no reply within the timeout
  flsd_msgs_ReplyStatus status = flsd_msgs_STATUS_INTERNAL;
  std::string message;
  std::string safety_report;
  std::vector<flsd_msgs_SkillInfo> skills;
  bool ok() const { return answered && status == flsd_msgs_STATUS_OK; }
  // "ok: ...", "not in control: ...", or "no reply within 2.0 s".
  std::string Describe() const;
};

// One state sample with its strings owned (the message's own string pointers are null).
struct StateSample {
  flsd_msgs_RobotState msg{};
  std::string backend, fault_message, controller;
  std::string task_client_id, task_call, task_message;
  std::vector<double> task_path;  // navigate: the planned path, x0 y0 x1 y1 ...
};

class Client {
 public:
  struct Options {
    int domain_id = 0;
    std::string partition = "flsd";
    std::string client_id;  // empty: host-pid-random
    std::chrono::milliseconds heartbeat{250};  // lease renewal period while in control
    // DDS Security (comm/security.h): the client's id is then its participant's authenticated
    // identity, the only one the server accepts from it; client_id must be empty or equal it.
    dds::SecurityConfig security;
  };

  explicit Client(const Options& options);
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // Waits until a server answers a status call; false if none does within `timeout`.
  bool WaitForServer(std::chrono::milliseconds timeout);

  CallResult Call(const std::string& call, const CallArgs& args = {},
                  std::chrono::milliseconds timeout = std::chrono::milliseconds(2000));

  // acquire_control / release_control, starting and stopping the lease heartbeat.
  CallResult AcquireControl(std::chrono::milliseconds timeout = std::chrono::milliseconds(2000));
  CallResult ReleaseControl(std::chrono::milliseconds timeout = std::chrono::milliseconds(2000));
  // Whether the heartbeat has been refused since control was acquired: the lease lapsed, or the
  // server restarted. Control is never re-taken silently; call AcquireControl again.
  bool lost_control() const { return lost_control_; }

  std::optional<StateSample> LatestState() const;
  // Waits for a state sample that satisfies `done`; returns it, or nullopt after `timeout`.
  std::optional<StateSample> WaitForState(const std::function<bool(const StateSample&)>& done,
                                          std::chrono::milliseconds timeout) const;

  const std::string& id() const { return id_; }

 private:
  void Background();
  static void OnReplies(dds_entity_t reader, void* self);
  void TakeReplies(dds_entity_t reader);

  std::string id_;
  Options options_;
  std::mutex call_mutex_;  // one call in flight: replies are matched by request id
  uint64_t next_request_id_ = 0;
  // The call in flight, completed by the reply listener on Cyclone's receive thread.
  std::mutex reply_mutex_;
  std::condition_variable reply_arrived_;
  uint64_t awaited_request_id_ = 0;
  CallResult awaited_result_;
  std::atomic<bool> reply_ready_{false};

  dds::Domain domain_;
  dds::Writer<flsd_msgs_Request> requests_;
  dds::Reader<flsd_msgs_RobotState> states_;
  dds::Guard wake_;
  dds::DataListener reply_listener_;
  dds::Reader<flsd_msgs_Reply> replies_;  // last: its listener may fire once it exists

  mutable std::mutex state_mutex_;
  mutable std::condition_variable state_arrived_;
  std::optional<StateSample> latest_;

  std::atomic<bool> in_control_{false}, lost_control_{false}, running_{true};
  std::thread background_;
};

}  // namespace flsd
