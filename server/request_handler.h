#pragma once
// Turns one DDS request into a reply and, when it asks for motion, into a ControlRequest for the
// controller; the OK reply to that waits for the tick that applies it (ReplyContent::ticket). Owns
// the control lease, per-client request ids and rate limits. Runs on the request thread; time is
// passed in, so tests need no sleeps. Every request gets a reply with a reason, except those
// dropped by the rate limit, which are counted.

#include <array>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

#include "comm/protocol.h"
#include "flsd_msgs.h"
#include "server/controller.h"
#include "server/lease.h"
#include "server/navigation/navigator.h"

namespace flsd {

struct ReplyContent {
  ReplyStatus status = ReplyStatus::kOk;
  std::string message;
  bool with_skills = false;   // list_skills: attach the library's skill descriptors
  std::string safety_report;  // safety trips this client has not been told of
  // Nonzero: the ticket of the request this call submitted (Controller::Submit). The reply is sent
  // only once the controller's status has reached it, so that the next request sees its effect.
  uint64_t ticket = 0;
  // With a ticket: revises the reply, before it is sent, with the status of a tick that has
  // applied its request. That tick may have refused what was accepted here (the robot went down,
  // or a stop latched, in between), it fixes who may clear the stop a damp latched, and it
  // carries the safety trips up to that tick. Runs on the sender's thread: of the handler's, it
  // touches only what a mutex of its own guards.
  std::function<void(ReplyContent&, const ControllerStatus&)> settle;
};

using DeferredReply = std::function<void(const ReplyContent&)>;

class RequestHandler {
 public:
  // `navigator` (may be null: navigate is then not available) must outlive the handler. The
  // default map (config.navigation.map) is read here; InputError if it is bad.
  RequestHandler(Controller& controller, const ServerConfig& config, Navigator* navigator = nullptr);

  // `now`: monotonic seconds; `wall_ns`: CLOCK_REALTIME ns (request deadlines are wall times).
  // nullopt: no reply now: dropped by the rate limit (counted in dropped()), or answered later
  // through `later`, from the navigator's thread (navigate with a map of its own, once the map is
  // read: reading it must not hold up the requests behind it).
  std::optional<ReplyContent> Handle(const flsd_msgs_Request& request, double now, int64_t wall_ns,
                                     const DeferredReply& later = nullptr);

  // Lets a silent controller's lease lapse; the robot then stands. Call at least every 50 ms.
  void Poll(double now);

  // The status of the tick the state topic showed last: call it after each sample is written and
  // before the replies that waited for that tick go out. A reply sent at once (status, a refusal,
  // a clear_stop with nothing latched) says what this status says, never a tick the topic has yet
  // to show, so a client that reads the topic after the reply never finds an older state there.
  // Until the first call (a handler with no state topic), the controller's own status. Any thread.
  void ShowStatus(const ControllerStatus& status);

  uint64_t dropped() const { return dropped_; }
  const std::string& controller_id() const { return lease_.holder(); }

  static constexpr std::size_t kMaxClientIdLength = sizeof(ClientId) - 1;
  // Per-client state is kept for this many clients; the longest silent is forgotten beyond it.
  static constexpr std::size_t kMaxClients = 256;
  // The highest request id of forgotten clients, by a hash of their ids: bounded memory, no replay.
  static constexpr std::size_t kIdFloorBuckets = 1024;

 private:
  struct ClientState {
    uint64_t last_request_id = 0;
    bool seen_request = false;
    double tokens = 0.0;
    double last_seen = 0.0;
  };

  ClientState& Client(const std::string& id, double now);
  static std::size_t FloorBucket(const std::string& id);
  bool TakeToken(ClientState& client, double now);
  // nullopt: answered through `later`.
  std::optional<ReplyContent> Dispatch(const flsd_msgs_Request& request, const std::string& client_id, double now,
                                       const DeferredReply& later);
  std::optional<ReplyContent> Motion(const flsd_msgs_Request& request, Call call, const std::string& client_id,
                                     const DeferredReply& later);
  std::optional<ReplyContent> Velocity(const flsd_msgs_Request& request, Call call, const std::string& client_id,
                                       const DeferredReply& later);
  // A stop of `client_id`'s task, never lost to a full queue, and of a navigation still reading its map.
  // `before` (nonzero): only a task that request preceded; the client may start the next at once.
  // Returns the stop's ticket.
  uint64_t StopTaskOf(const std::string& client_id, TaskState state, const std::string& reason,
                      uint64_t before = 0);
  // Tells the controller who holds the lease now, so that the state topic names the holder from
  // the tick that applies it. Returns that request's ticket: a reply to a call that changed the
  // holder waits for it.
  uint64_t AnnounceHolder();
  // Why the robot cannot start moving now (a latched stop, a hazard), or empty.
  std::string MotionBlocked(const ControllerStatus& status) const;
  // Who may clear the latched emergency stop, and how; what forbids stiffening the joints and its remedy.
  std::string EmergencyStopText(const ControllerStatus& status) const;
  std::string HazardText(const ControllerStatus& status) const;
  // ReplyContent::settle for `client_id`'s `call`: a call the tick may refuse is answered with the
  // refusal the handler gives when it sees the cause first; a damp says who may clear the stop.
  std::function<void(ReplyContent&, const ControllerStatus&)> Settle(Call call, const std::string& client_id) const;
  ReplyContent ClearStop(const std::string& client_id);
  // The request's ticket, or 0 if the queue is full.
  uint64_t Submit(ControlRequest request, const std::string& client_id, uint64_t request_id);
  std::string StatusText(const ControllerStatus& status) const;
  // What the handler answers at once from (ShowStatus).
  ControllerStatus Shown() const;
  // Puts the safety trips `status` counts that `client_id` has not been told of in `reply`'s
  // safety_report. On the request thread for a reply sent at once, on the sender's for one that
  // waited for a tick (its settle), with that tick's status.
  void ReportTrips(const std::string& client_id, const ControllerStatus& status, ReplyContent& reply);

  Controller& controller_;
  ServerConfig config_;
  Navigator* navigator_;
  std::optional<Map2D> default_map_;
  ControlLease lease_;
  std::unordered_map<std::string, ClientState> clients_;
  std::array<uint64_t, kIdFloorBuckets> id_floors_{};  // only rise
  uint64_t dropped_ = 0;
  std::mutex trips_mutex_;
  std::unordered_map<std::string, uint64_t> reported_trips_;  // per client, under trips_mutex_
  mutable std::mutex shown_mutex_;
  std::optional<ControllerStatus> shown_;  // under shown_mutex_
};

}  // namespace flsd
