#pragma once
// flsd::Client: calls skilld over DDS and follows its state topic. Calls are synchronous with a
// timeout; while the client holds control, a background thread renews the lease, so a client
// process that dies lets the robot stand within the lease timeout. (A client whose main thread
// hangs keeps renewing: give long motions a duration, which the server enforces.)
//
// The typed calls (ListSkills, ExecuteSkill, ...) speak the client's own types (client/types.h);
// a long call returns a Task to wait on. Call() sends any call by name, as the wire carries it.

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "client/types.h"
#include "comm/dds.h"
#include "comm/protocol.h"
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
  Reply reply() const;
  std::string Describe() const { return reply().Describe(); }
};

// One state sample with its strings owned (the message's own string pointers are null).
struct StateSample {
  flsd_msgs_RobotState msg{};
  std::string backend, fault_message, controller;
  std::string task_client_id, task_call, task_message;
  std::vector<double> task_path;  // navigate: the planned path, x0 y0 x1 y1 ...
};

class Task;

class Client {
 public:
  static constexpr std::chrono::milliseconds kCallTimeout{2000};

  struct Options {
    int domain_id = 0;
    std::string partition = "flsd";
    std::string client_id;  // empty: host-pid-random
    std::chrono::milliseconds heartbeat{250};  // lease renewal period while in control
    // DDS Security (comm/security.h): the client's id is then its participant's authenticated
    // identity, the only one the server accepts from it; client_id must be empty or equal it.
    dds::SecurityConfig security;
    // Reads the state only: no request writer or reply reader, which DDS Security refuses an
    // observer's identity; every call comes back unanswered.
    bool read_only = false;
  };

  explicit Client(const Options& options);
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  // Waits until a server answers a status call; false if none does within `timeout`.
  bool WaitForServer(std::chrono::milliseconds timeout);

  // Any call by its name on the wire (comm/protocol.h lists them).
  CallResult Call(const std::string& call, const CallArgs& args = {}, std::chrono::milliseconds timeout = kCallTimeout);

  // The library's skills; CallError if the server does not give them.
  std::vector<SkillInfo> ListSkills(std::chrono::milliseconds timeout = kCallTimeout);
  // The message says the mode, the time, who holds control and the faults.
  Reply Status(std::chrono::milliseconds timeout = kCallTimeout);
  // Long calls: the Task's reply says whether the server accepted it. They need control.
  Task ExecuteSkill(int skill, double duration, std::chrono::milliseconds timeout = kCallTimeout);
  Task TrackVelocity(double vx, double vy, double wz, double duration,
                     std::chrono::milliseconds timeout = kCallTimeout);
  // map_yaml: a map's YAML text, empty for the server's; duration 0: the server's timeout.
  Task Navigate(double x, double y, const std::string& map_yaml = "", double duration = 0.0,
                std::chrono::milliseconds timeout = kCallTimeout);
  Reply Stop(std::chrono::milliseconds timeout = kCallTimeout);
  Reply Stand(std::chrono::milliseconds timeout = kCallTimeout);
  Reply Reset(std::chrono::milliseconds timeout = kCallTimeout);
  // The emergency stop, open to every client; it latches until ClearStop.
  Reply Damp(std::chrono::milliseconds timeout = kCallTimeout);
  Reply ClearStop(std::chrono::milliseconds timeout = kCallTimeout);

  // acquire_control / release_control, starting and stopping the lease heartbeat.
  Reply AcquireControl(std::chrono::milliseconds timeout = kCallTimeout);
  Reply ReleaseControl(std::chrono::milliseconds timeout = kCallTimeout);
  // Whether the heartbeat has been refused since control was acquired: the lease lapsed, or the
  // server restarted. Control is never re-taken silently; call AcquireControl again.
  bool lost_control() const { return lost_control_; }

  // The newest state sample, typed; nullopt before the first.
  std::optional<StateReport> State() const;
  // The first sample newer than tick `after`; nullopt after `timeout`.
  std::optional<StateReport> NextState(uint64_t after, std::chrono::milliseconds timeout) const;
  // The state topic's latest report of this client's long call `request_id` (state kNone if it
  // has not reported it), and a wait for its end.
  TaskReport TaskProgress(uint64_t request_id) const;
  bool WaitForTask(uint64_t request_id, std::chrono::milliseconds timeout) const;

  std::optional<StateSample> LatestState() const;
  // Waits for a state sample that satisfies `done`; returns it, or nullopt after `timeout`.
  std::optional<StateSample> WaitForState(const std::function<bool(const StateSample&)>& done,
                                          std::chrono::milliseconds timeout) const;

  const std::string& id() const { return id_; }

 private:
  void Background();
  // One call, call_mutex_ held.
  CallResult Send(const std::string& call, const CallArgs& args, std::chrono::milliseconds timeout);
  static void OnReplies(dds_entity_t reader, void* self);
  void TakeReplies(dds_entity_t reader);
  Reply Simple(flsd::Call call, std::chrono::milliseconds timeout);
  Task Long(flsd::Call call, const CallArgs& args, std::chrono::milliseconds timeout);
  // Keeps the reports of this client's recent tasks: state_mutex_ held.
  void TrackTasks(const StateSample& sample);

  std::string id_;
  Options options_;
  std::mutex call_mutex_;  // one call in flight: replies are matched by request id
  // The server reports a safety trip once, in the next reply to this client: one that came with
  // a lease heartbeat is handed to the user's next call (call_mutex_ held).
  std::string unreported_safety_;
  uint64_t next_request_id_ = 0;
  // The call in flight, completed by the reply listener on Cyclone's receive thread.
  std::mutex reply_mutex_;
  std::condition_variable reply_arrived_;
  uint64_t awaited_request_id_ = 0;
  CallResult awaited_result_;
  std::atomic<bool> reply_ready_{false};

  dds::Domain domain_;
  std::optional<dds::Writer<flsd_msgs_Request>> requests_;  // none when read_only
  dds::Reader<flsd_msgs_RobotState> states_;
  dds::Guard wake_;
  dds::DataListener reply_listener_;
  std::optional<dds::Reader<flsd_msgs_Reply>> replies_;  // last: its listener may fire once it exists

  mutable std::mutex state_mutex_;
  mutable std::condition_variable state_arrived_;
  std::optional<StateSample> latest_;
  std::map<uint64_t, TaskReport> tasks_;  // this client's recent long calls by request id

  std::atomic<bool> in_control_{false}, lost_control_{false}, running_{true};
  std::thread background_;
};

// A long call: accepted or refused, then running until it ends. Its client must outlive it.
class Task {
 public:
  Task(const Client& client, Reply reply) : client_(&client), reply_(std::move(reply)) {}
  const Reply& reply() const { return reply_; }
  bool accepted() const { return reply_.ok(); }
  uint64_t request_id() const { return reply_.request_id; }
  TaskReport Progress() const;
  // Refused, or ended (its result is Progress()).
  bool Done() const;
  // True once Done; false if still running after `timeout`.
  bool Wait(std::chrono::milliseconds timeout) const;
  bool Succeeded() const { return Progress().state == TaskState::kSucceeded; }

 private:
  const Client* client_;
  Reply reply_;
};

}  // namespace flsd
