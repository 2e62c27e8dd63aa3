#pragma once
// skilld's DDS face. Requests are handled on Cyclone's receive thread as they arrive (a data
// listener: no thread hand-off, so a damp reaches the controller within microseconds); a poll
// thread lets silent leases lapse; a telemetry thread publishes one state sample per control
// tick, then sends the replies that waited for that tick: an OK reply to a call the controller
// applies (the lease's holder too, which the state topic names) goes out once it has, after the
// sample that shows it, so that the next request, from any client, sees its effect, while the
// receive thread never waits for a tick. None touches the robot; all go through the
// Controller. With DDS Security on, a request is executed only if its client_id is its writer's
// authenticated identity (comm/security.h), so the lease, request ids and rate limits all belong
// to identities; motion calls are audited.

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "comm/dds.h"
#include "server/audit_log.h"
#include "server/control_loop.h"
#include "server/request_handler.h"

namespace flsd {

class DdsService {
 public:
  // `controller` and `loop` must outlive the service.
  DdsService(const ServerConfig& config, Controller& controller, const ControlLoop& loop, std::string backend_name);
  ~DdsService() { Stop(); }

  void Start();
  void Stop();

  uint64_t replies_sent() const { return replies_sent_.load(); }

 private:
  static void OnRequests(dds_entity_t reader, void* self);
  void ServeRequests();  // takes and answers whatever requests are waiting
  // The authenticated identity of the writer of a request (cached: one lookup per writer).
  const std::string& IdentityOf(dds_instance_handle_t publication);
  void PollLeases();
  void PublishState();
  // Sends `content` now, or once status().applied reaches its ticket (ReplyContent::ticket).
  void Answer(const ReplyContent& content, const DeferredReply& send);
  // Sends the waiting replies whose requests the controller has applied (up to `status`.applied),
  // as `status` settles them (ReplyContent::settle), and, as an error, those that have waited past
  // kApplyTimeout.
  void AnswerApplied(const ControllerStatus& status);
  // Thread-safe: the navigator answers navigate requests whose maps it has read.
  void SendReply(const std::string& client_id, uint64_t request_id, int64_t deadline_ns, const ReplyContent& content);

  Controller& controller_;
  const ControlLoop& loop_;
  std::string backend_name_;
  dds::Domain domain_;
  dds::Writer<flsd_msgs_Reply> replies_;
  dds::Writer<flsd_msgs_RobotState> states_;
  // After the writers, so that it goes first: its thread may be answering a request.
  std::unique_ptr<Navigator> navigator_;  // when the library has a skill selector
  // The listener and the poll thread share the handler. Everything under it is quick (a map is
  // read on the navigator's thread), so an emergency stop never waits here for long.
  std::mutex handler_mutex_;
  RequestHandler handler_;
  AuditLog audit_;
  std::unordered_map<dds_instance_handle_t, std::string> identities_;  // under handler_mutex_
  std::vector<flsd_msgs_SkillInfo> skills_;
  std::atomic<bool> running_{false};
  std::mutex poll_mutex_;
  std::condition_variable poll_wake_;
  std::thread poll_thread_, state_thread_;
  std::atomic<uint64_t> replies_sent_{0};
  // Replies waiting for the controller to apply their requests; far longer than a tick means the
  // control loop has stalled.
  struct WaitingReply {
    ReplyContent content;
    DeferredReply send;
    double give_up;  // monotonic s
  };
  static constexpr double kApplyTimeout = 1.0;  // s
  std::mutex waiting_mutex_;
  std::vector<WaitingReply> waiting_;
  std::atomic<uint64_t> dropped_{0};

  // Last, so that they go first: the listener may fire as soon as the reader exists, and uses
  // every member above. Stop() removes it before anything is torn down.
  dds::DataListener listener_;
  dds::Reader<flsd_msgs_Request> requests_;
};

}  // namespace flsd
