#include "server/request_handler.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>

#include "comm/protocol.h"
#include "core/check.h"

namespace flsd {
namespace {

ReplyContent Reply(ReplyStatus status, std::string message) {
  ReplyContent r;
  r.status = status;
  r.message = std::move(message);
  return r;
}

// An OK reply to a call that the next control tick applies: sent once it has (ReplyContent::ticket),
// as `settle` revises it.
ReplyContent Applied(uint64_t ticket, std::string message,
                     std::function<void(ReplyContent&, const ControllerStatus&)> settle = nullptr) {
  ReplyContent r = Reply(ReplyStatus::kOk, std::move(message));
  r.ticket = ticket;
  r.settle = std::move(settle);
  return r;
}

bool AllFinite(const double* values, int n) {
  return std::all_of(values, values + n, [](double v) { return std::isfinite(v); });
}

// std::to_chars rather than snprintf: `status` formats one on every call, and printf's float
// path was a tenth of skilld's own time per status request (a profile of its receive thread).
std::string Seconds(double s) {
  char text[40];
  const std::to_chars_result end = std::to_chars(text, text + sizeof text, s, std::chars_format::fixed, 2);
  if (end.ec != std::errc()) return std::to_string(s) + " s";
  return std::string(text, end.ptr) + " s";
}

// Empty if `duration` is in (0, max].
std::string DurationError(double duration, double max) {
  if (std::isfinite(duration) && duration > 0.0 && duration <= max) return "";
  return "duration must be in (0, " + Seconds(max) + "], got " + std::to_string(duration);
}

// The words of a refusal that need none of the handler's state, so that a reply settled on the
// telemetry thread (ReplyContent::settle) says what the handler says.
struct RefusalTexts {
  double hold_time;  // safety.stop_hold_time
  bool can_reset;    // the backend can put a fallen robot back

  // Who may clear the emergency stop latched in `status`, and when.
  std::string Stop(const ControllerStatus& status) const {
    const StopPresses& stop = status.stop;
    const std::string who = stop.client[0] != '\0' ? stop.client.data() : "the server";
    if (stop.other_client[0] == '\0') {
      return "an emergency stop from " + who + " is latched; call clear_stop (" + who +
             " may at once, any client after " + Seconds(hold_time) + "), then stand";
    }
    const std::string other = stop.other_client.data();
    return "emergency stops from " + who + " and from " + other + " are latched; call clear_stop (" + who + " may " +
           Seconds(hold_time) + " after " + other + "'s press, any client " + Seconds(hold_time) + " after " + who +
           "'s), then stand";
  }
  std::string CannotClear(const ControllerStatus& status, const std::string& client) const {
    const double left = status.stop.ClearableAt(client.c_str(), hold_time) - status.time;
    return Stop(status) + " (" + Seconds(std::max(0.0, left)) + " left)";
  }
  // The remedy for the cause, not a guess: a robot on its side and a joint out of range are
  // fixed by hand; a backend fault's own account (a motor out of servo mode, no frames) says what
  // is wrong, and only the robot can fix it.
  std::string Remedy(uint32_t hazards) const {
    if (can_reset) return "; call reset";
    if (hazards & kFaultTilt) return "; put the robot upright";
    if (hazards & kFaultJointRange) return "; move the joint back into its range";
    return "";
  }
  // Why a motion cannot start: `latched` faults (`fault_message`), else `hazards` (`described`).
  std::string Blocked(const ControllerStatus& status, uint32_t latched, const char* fault_message, uint32_t hazards,
                      const char* described) const {
    if (latched & kFaultStop) return Stop(status);
    if (latched != 0) return std::string("a safety stop is latched (") + fault_message + "); call stand first";
    if (hazards != 0) return "cannot start moving: " + (described + Remedy(hazards));
    return "";
  }
};

RefusalTexts TextsOf(const ServerConfig& config, const Controller& controller) {
  return {config.safety.stop_hold_time, controller.backend_can_reset()};
}

}  // namespace

RequestHandler::RequestHandler(Controller& controller, const ServerConfig& config, Navigator* navigator)
    : controller_(controller), config_(config), navigator_(navigator), lease_(config.lease_timeout) {
  if (!config.navigation.map.empty()) default_map_ = Map2D::Load(config.navigation.map);
}

RequestHandler::ClientState& RequestHandler::Client(const std::string& id, double now) {
  auto it = clients_.find(id);
  if (it == clients_.end()) {
    if (clients_.size() >= kMaxClients) {  // forget the longest-silent client, but not its ids
      auto oldest = std::min_element(clients_.begin(), clients_.end(), [](const auto& a, const auto& b) {
        return a.second.last_seen < b.second.last_seen;
      });
      uint64_t& floor = id_floors_[FloorBucket(oldest->first)];
      if (oldest->second.seen_request) floor = std::max(floor, oldest->second.last_request_id);
      {
        std::lock_guard<std::mutex> lock(trips_mutex_);
        reported_trips_.erase(oldest->first);
      }
      clients_.erase(oldest);
    }
    ClientState fresh;
    // A client the server does not know may be one it forgot: its ids must clear the floor of
    // its bucket, so that a forgotten request cannot be replayed.
    const uint64_t floor = id_floors_[FloorBucket(id)];
    fresh.seen_request = floor > 0;
    fresh.last_request_id = floor;
    fresh.tokens = config_.request_burst;
    fresh.last_seen = now;
    it = clients_.emplace(id, fresh).first;
    const uint64_t trips = Shown().safety_trips;  // a newcomer hears of trips to come
    std::lock_guard<std::mutex> lock(trips_mutex_);
    reported_trips_[id] = trips;
  }
  return it->second;
}

std::size_t RequestHandler::FloorBucket(const std::string& id) {
  return std::hash<std::string>{}(id) % kIdFloorBuckets;
}

bool RequestHandler::TakeToken(ClientState& client, double now) {
  client.tokens = std::min<double>(config_.request_burst,
                                   client.tokens + (now - client.last_seen) * config_.requests_per_second);
  client.last_seen = now;
  if (client.tokens < 1.0) return false;
  client.tokens -= 1.0;
  return true;
}

void RequestHandler::Poll(double now) {
  const std::string holder = lease_.holder();
  if (lease_.Expire(now)) {
    AnnounceHolder();
    StopTaskOf(holder, TaskState::kLeaseLost,
               "control lease of " + holder + " lapsed after " + Seconds(lease_.timeout()) + " without a request; standing");
  }
}

uint64_t RequestHandler::StopTaskOf(const std::string& client_id, TaskState state, const std::string& reason,
                                    uint64_t before) {
  if (navigator_ != nullptr) navigator_->Cancel();
  ControlRequest stop;
  stop.kind = ControlRequest::Kind::kStop;
  stop.stop_state = state;
  // Only this client's task: not one its successor may already have started in the same tick.
  stop.scope = ControlRequest::Scope::kClient;
  stop.request_id = before;
  SetText(stop.client_id, client_id.c_str());
  SetText(stop.reason, reason.c_str());
  return controller_.SubmitUrgent(stop);
}

uint64_t RequestHandler::AnnounceHolder() {
  ControlRequest holder;
  holder.kind = ControlRequest::Kind::kHolder;
  SetText(holder.client_id, lease_.holder().c_str());
  return controller_.SubmitUrgent(holder);
}

std::optional<ReplyContent> RequestHandler::Handle(const flsd_msgs_Request& request, double now, int64_t wall_ns,
                                                   const DeferredReply& later) {
  Poll(now);
  const std::string client_id = request.header.client_id != nullptr ? request.header.client_id : "";
  if (client_id.empty() || client_id.size() > kMaxClientIdLength) {
    return Reply(ReplyStatus::kInvalidArgument,
                 "client_id must have 1 to " + std::to_string(kMaxClientIdLength) + " characters");
  }
  ClientState& client = Client(client_id, now);
  if (!TakeToken(client, now)) {
    ++dropped_;
    return std::nullopt;
  }
  const uint64_t id = request.header.request_id;
  if (client.seen_request && id <= client.last_request_id) {
    return Reply(ReplyStatus::kDuplicate, "request_id " + std::to_string(id) + " is not above " +
                                                 std::to_string(client.last_request_id) +
                                                 ", the last one from this client or its forgotten peers; not executed");
  }
  client.seen_request = true;
  client.last_request_id = id;
  const int64_t deadline = request.header.deadline_ns;
  if (deadline < 0) {
    return Reply(ReplyStatus::kInvalidArgument, "deadline_ns must be 0 (none) or a CLOCK_REALTIME time in ns, got " +
                                                        std::to_string(deadline) + "; not executed");
  }
  if (deadline != 0 && wall_ns > deadline) {  // both non-negative: the difference cannot overflow
    return Reply(ReplyStatus::kDeadlineExceeded,
                 "arrived " + Seconds(static_cast<double>(wall_ns - deadline) * 1e-9) + " after its deadline; not executed");
  }
  // Any request that gets this far shows the holder is alive: it renews the lease.
  lease_.Renew(client_id, now);

  std::optional<ReplyContent> reply = Dispatch(request, client_id, now, later);
  if (!reply) return reply;
  if (reply->ticket == 0) {
    ReportTrips(client_id, Shown(), *reply);
  } else {  // as of the tick the reply waits for: a trip in that tick precedes the reply
    reply->settle = [this, client_id, settle = std::move(reply->settle)](ReplyContent& r, const ControllerStatus& s) {
      if (settle) settle(r, s);
      ReportTrips(client_id, s, r);
    };
  }
  return reply;
}

void RequestHandler::ReportTrips(const std::string& client_id, const ControllerStatus& status, ReplyContent& reply) {
  std::lock_guard<std::mutex> lock(trips_mutex_);
  const auto reported = reported_trips_.find(client_id);  // gone: the client was forgotten meanwhile
  if (reported == reported_trips_.end() || status.safety_trips <= reported->second) return;
  reply.safety_report = status.fault_message[0] != '\0' ? status.fault_message.data() : "safety stop";
  reported->second = status.safety_trips;
}

std::optional<ReplyContent> RequestHandler::Dispatch(const flsd_msgs_Request& request, const std::string& client_id,
                                                     double now, const DeferredReply& later) {
  const std::string name = request.call != nullptr ? request.call : "";
  const std::optional<Call> found = FindCall(name);
  if (!found) return Reply(ReplyStatus::kUnknownCall, "unknown call '" + name + "'; known calls: " + KnownCalls());
  const Call call = *found;
  if (call == Call::kListSkills) {
    ReplyContent r = Reply(ReplyStatus::kOk, std::to_string(controller_.library().num_skills()) + " skills");
    r.with_skills = true;
    return r;
  }
  if (call == Call::kStatus) return Reply(ReplyStatus::kOk, StatusText(Shown()));
  if (call == Call::kAcquireControl) {
    if (!lease_.Acquire(client_id, now)) {
      return Reply(ReplyStatus::kNotInControl, "control is held by " + lease_.holder());
    }
    return Applied(AnnounceHolder(), "control granted; it lapses after " + Seconds(lease_.timeout()) +
                                         " without a request from this client");
  }
  if (call == Call::kRenewControl) {  // a heartbeat: never grants a lease that is not held
    if (!lease_.Renew(client_id, now)) {
      return Reply(ReplyStatus::kNotInControl, lease_.held() ? "control is held by " + lease_.holder()
                                                                  : std::string("this client does not hold control"));
    }
    return Reply(ReplyStatus::kOk, "control renewed");
  }
  if (call == Call::kReleaseControl) {
    if (!lease_.Release(client_id)) {
      return Reply(ReplyStatus::kNotInControl, "this client does not hold control");
    }
    AnnounceHolder();  // its ticket is below the stop's, which the reply waits for
    return Applied(StopTaskOf(client_id, TaskState::kCancelled, "control released", request.header.request_id),
                   "control released; the robot stands");
  }
  if (call == Call::kDamp) {  // the emergency stop: anyone may press it
    ControlRequest damp;
    damp.kind = ControlRequest::Kind::kDamp;
    SetText(damp.reason, ("emergency stop from " + client_id).c_str());
    SetText(damp.client_id, client_id.c_str());
    damp.request_id = request.header.request_id;
    const uint64_t ticket = controller_.SubmitUrgent(damp);
    return Applied(ticket,
                   "damping; latched until clear_stop (from this client, or from any after " +
                       Seconds(config_.safety.stop_hold_time) + "), then stand",
                   Settle(call, client_id));
  }
  if (call == Call::kClearStop) return ClearStop(client_id);
  FLSD_DEMAND(Spec(call).needs_control);  // every other call moves the robot
  if (!lease_.Renew(client_id, now)) {
    return Reply(ReplyStatus::kNotInControl,
                 lease_.held() ? "control is held by " + lease_.holder()
                               : std::string("no client holds control; call acquire_control first"));
  }
  return Motion(request, call, client_id, later);
}

std::optional<ReplyContent> RequestHandler::Motion(const flsd_msgs_Request& request, Call call,
                                                   const std::string& client_id, const DeferredReply& later) {
  const ControllerStatus status = Shown();
  ControlRequest control;
  if (call == Call::kExecuteSkill) {
    const int k = request.skill;
    if (k < 0 || k >= controller_.library().num_skills()) {
      return Reply(ReplyStatus::kInvalidArgument, "skill " + std::to_string(k) + " is not in [0, " +
                                                          std::to_string(controller_.library().num_skills()) + ")");
    }
    if (const std::string why = DurationError(request.duration, config_.max_duration); !why.empty()) {
      return Reply(ReplyStatus::kInvalidArgument, why);
    }
    const SkillDescriptor& skill = controller_.library().skills()[k];
    // A real robot is the randomised case: a skill that fell there is as unsafe.
    if (const std::string why = WhyUndependable(skill, config_.safety.min_skill_survival); !why.empty()) {
      return Reply(ReplyStatus::kNotAvailable, "skill " + std::to_string(k) + " " + why +
                                                   " (safety.min_skill_survival = " +
                                                   std::to_string(config_.safety.min_skill_survival) + "); it is not run");
    }
    if (const std::string blocked = MotionBlocked(status); !blocked.empty()) {
      return Reply(ReplyStatus::kSafetyStop, blocked);
    }
    control.kind = ControlRequest::Kind::kSkill;
    control.skill = k;
    control.duration = request.duration;
    const uint64_t ticket = Submit(control, client_id, request.header.request_id);
    if (ticket == 0) return Reply(ReplyStatus::kInternal, "the control queue is full; retry");
    return Applied(ticket,
                   "skill " + std::to_string(k) + " for " + Seconds(request.duration) +
                       " accepted; progress is on the state topic",
                   Settle(call, client_id));
  }
  if (call == Call::kTrackVelocity || call == Call::kNavigate) return Velocity(request, call, client_id, later);
  if (call == Call::kReset && !controller_.backend_can_reset()) {
    return Reply(ReplyStatus::kNotAvailable, "this backend cannot reset the robot; stand it up by hand");
  }
  if ((call == Call::kStand || call == Call::kReset) && (status.faults & kFaultStop)) {
    return Reply(ReplyStatus::kSafetyStop, std::string("cannot ") + CallName(call) + ": " + EmergencyStopText(status));
  }
  if (call == Call::kStand && status.hazards != 0) {
    // Standing clears a latched stop, but only once the robot is upright, in range and sensed.
    return Reply(ReplyStatus::kSafetyStop, "cannot stand: " + HazardText(status));
  }
  control.kind = call == Call::kStand ? ControlRequest::Kind::kStand
                 : call == Call::kStop ? ControlRequest::Kind::kStop
                                            : ControlRequest::Kind::kReset;
  SetText(control.reason, ("stopped by " + client_id).c_str());
  const uint64_t ticket = Submit(control, client_id, request.header.request_id);
  if (ticket == 0) return Reply(ReplyStatus::kInternal, "the control queue is full; retry");
  return Applied(ticket,
                 call == Call::kStand  ? "standing"
                 : call == Call::kStop ? "stopping; the robot stands"
                                       : "reset",
                 Settle(call, client_id));
}

std::string RequestHandler::MotionBlocked(const ControllerStatus& status) const {
  char described[192];
  DescribeFaults(status.hazards, status.state, config_.safety, described, sizeof described,
                 status.backend_fault.data());
  return TextsOf(config_, controller_)
      .Blocked(status, status.faults, status.fault_message.data(), status.hazards, described);
}

std::string RequestHandler::EmergencyStopText(const ControllerStatus& status) const {
  return TextsOf(config_, controller_).Stop(status);
}

std::string RequestHandler::HazardText(const ControllerStatus& status) const {
  char text[192];
  DescribeFaults(status.hazards, status.state, config_.safety, text, sizeof text, status.backend_fault.data());
  return text + TextsOf(config_, controller_).Remedy(status.hazards);
}

std::function<void(ReplyContent&, const ControllerStatus&)> RequestHandler::Settle(Call call,
                                                                                   const std::string& client_id) const {
  const RefusalTexts texts = TextsOf(config_, controller_);
  if (call == Call::kDamp) {
    // Another client's press in the same tick is as much a stop: this one alone no longer clears it.
    return [texts, client_id](ReplyContent& reply, const ControllerStatus& status) {
      if (!(status.faults & kFaultStop)) {
        reply.message = "damped; the emergency stop has been cleared since";
      } else if (status.stop.other_client[0] != '\0' || client_id != status.stop.client.data()) {
        reply.message = "damping; " + texts.Stop(status);
      }
    };
  }
  const Controller* controller = &controller_;
  return [controller, texts, call, client_id](ReplyContent& reply, const ControllerStatus& status) {
    ApplyRefusal refusal;
    switch (controller->OutcomeOf(reply.ticket, &refusal)) {
      case Controller::Outcome::kApplied: return;
      case Controller::Outcome::kUnknown:
        reply.status = ReplyStatus::kInternal;
        reply.message = "the control loop has applied the request, but its outcome is no longer on record; call status";
        return;
      case Controller::Outcome::kRefused: break;
    }
    reply.status = ReplyStatus::kSafetyStop;
    if (call == Call::kClearStop) {
      reply.message = texts.CannotClear(status, client_id);
    } else if ((call == Call::kStand || call == Call::kReset) && (refusal.latched & kFaultStop)) {
      reply.message = std::string("cannot ") + CallName(call) + ": " + texts.Stop(status);
    } else if (call == Call::kStand) {
      reply.message = "cannot stand: " + (refusal.reason.data() + texts.Remedy(refusal.hazards));
    } else {
      const char* why = refusal.reason.data();
      reply.message = texts.Blocked(status, refusal.latched, why, refusal.hazards, why);
    }
  };
}

ReplyContent RequestHandler::ClearStop(const std::string& client_id) {
  const ControllerStatus status = Shown();
  if (!(status.faults & kFaultStop)) return Reply(ReplyStatus::kOk, "no emergency stop is latched");
  // Nobody, a presser included, undoes another client's press before the hold time has passed since it.
  if (status.time < status.stop.ClearableAt(client_id.c_str(), config_.safety.stop_hold_time)) {
    return Reply(ReplyStatus::kSafetyStop, TextsOf(config_, controller_).CannotClear(status, client_id));
  }
  ControlRequest clear;
  clear.kind = ControlRequest::Kind::kClearStop;
  SetText(clear.client_id, client_id.c_str());
  const uint64_t ticket = controller_.Submit(clear);
  if (ticket == 0) return Reply(ReplyStatus::kInternal, "the control queue is full; retry");
  return Applied(ticket, "emergency stop cleared; the robot stays damped until stand",
                 Settle(Call::kClearStop, client_id));
}

std::optional<ReplyContent> RequestHandler::Velocity(const flsd_msgs_Request& request, Call call,
                                                     const std::string& client_id, const DeferredReply& later) {
  const bool navigation = call == Call::kNavigate;
  if (!controller_.selector(navigation)) {
    return Reply(ReplyStatus::kNotAvailable,
                 std::string(CallName(call)) + " is not available: the skill library " +
                     controller_.library().path() + " has no skill selector (flsd export-selector adds one) and the " +
                     "server's " + (navigation ? "navigation.selector" : "selector") + " is '" +
                     (navigation ? config_.navigation.selector : config_.selector) + "'");
  }
  ControlRequest control;
  control.kind = ControlRequest::Kind::kVelocity;
  std::string accepted;
  std::optional<NavigationJob> job;
  std::string map_yaml;
  if (call == Call::kTrackVelocity) {
    if (!AllFinite(request.velocity, 3)) return Reply(ReplyStatus::kInvalidArgument, "velocity must be finite");
    if (const std::string why = DurationError(request.duration, config_.max_duration); !why.empty()) {
      return Reply(ReplyStatus::kInvalidArgument, why);
    }
    std::copy(request.velocity, request.velocity + 3, control.velocity.begin());
    control.duration = request.duration;
    const HierarchicalPolicy& selector = *controller_.selector();
    const std::array<std::array<double, 3>, 2> range = selector.CommandRange();
    char text[256];
    std::snprintf(text, sizeof text, "velocity (%.2f m/s, %.2f m/s, %.2f rad/s) for %s accepted", control.velocity[0],
                  control.velocity[1], control.velocity[2], Seconds(request.duration).c_str());
    accepted = text;
    for (int a = 0; a < 3; ++a) {
      const double clipped = std::clamp(control.velocity[a], range[0][a], range[1][a]);
      if (clipped != control.velocity[a]) {
        static const char* const kAxes[] = {"vx", "vy", "wz"};
        std::snprintf(text, sizeof text, "; %s clipped to %.2f, the edge of the %s selector's range [%.2f, %.2f]",
                      kAxes[a], clipped, ToString(selector.kind()), range[0][a], range[1][a]);
        accepted += text;
      }
    }
    const std::array<double, 3> seen = selector.Clip(control.velocity.data());
    if (selector.MinPlanarSpeed() > 0.0 && seen[0] == 0.0 && seen[1] == 0.0 &&
        (control.velocity[0] != 0.0 || control.velocity[1] != 0.0)) {
      std::snprintf(text, sizeof text, "; vx and vy zeroed: slower than %.2f m/s, as in training",
                    selector.MinPlanarSpeed());
      accepted += text;
    }
  } else {
    if (!AllFinite(request.goal, 2)) return Reply(ReplyStatus::kInvalidArgument, "goal must be finite");
    if (navigator_ == nullptr) return Reply(ReplyStatus::kNotAvailable, "navigate is not available on this server");
    job.emplace();
    job->goal = Eigen::Vector2d(request.goal[0], request.goal[1]);
    map_yaml = request.map_yaml != nullptr ? request.map_yaml : "";
    if (map_yaml.size() > Map2D::kMaxTextBytes) {  // read on the navigator's thread, but not kept unread
      return Reply(ReplyStatus::kInvalidArgument, "map_yaml has " + std::to_string(map_yaml.size()) +
                                                          " bytes; a map may have at most " +
                                                          std::to_string(Map2D::kMaxTextBytes));
    }
    if (!map_yaml.empty()) {
      FLSD_DEMAND(later != nullptr);  // the caller must take a reply from the navigator's thread
    } else if (default_map_) {
      job->map = *default_map_;
    } else {
      return Reply(ReplyStatus::kInvalidArgument,
                   "no map: send one with the request, or name one in the server config (navigation.map)");
    }
    // A duration, if given, bounds this navigation; otherwise the server's navigation.timeout.
    job->timeout = config_.navigation.timeout;
    if (request.duration != 0.0) {
      if (const std::string why = DurationError(request.duration, config_.max_duration); !why.empty()) {
        return Reply(ReplyStatus::kInvalidArgument, why);
      }
      job->timeout = request.duration;
    }
    control.navigate = true;
    control.duration = job->timeout + 1.0;  // the navigator times out first, with a message
    char text[192];
    std::snprintf(text, sizeof text, "navigation to (%.2f, %.2f) accepted; planning", job->goal.x(), job->goal.y());
    accepted = text;
  }
  if (const std::string blocked = MotionBlocked(Shown()); !blocked.empty()) {
    return Reply(ReplyStatus::kSafetyStop, blocked);
  }
  accepted += "; progress is on the state topic";
  if (job) {
    SetText(job->client_id, client_id.c_str());
    job->request_id = request.header.request_id;
  }
  if (!map_yaml.empty()) {  // the navigator reads the map, submits the task and answers
    navigator_->Cancel();
    SetText(control.client_id, client_id.c_str());
    control.request_id = request.header.request_id;
    auto settle = Settle(call, client_id);
    navigator_->Start(MapRequest{std::move(*job), std::move(map_yaml), control, accepted,
                                 [later, settle](ReplyStatus status, const std::string& message, uint64_t ticket) {
                                   ReplyContent r = Reply(status, message);
                                   r.ticket = ticket;
                                   if (ticket != 0) r.settle = settle;
                                   later(r);
                                 }});
    return std::nullopt;
  }
  const uint64_t ticket = Submit(control, client_id, request.header.request_id);
  if (ticket == 0) return Reply(ReplyStatus::kInternal, "the control queue is full; retry");
  if (job) navigator_->Start(std::move(*job));
  return Applied(ticket, accepted, Settle(call, client_id));
}

uint64_t RequestHandler::Submit(ControlRequest request, const std::string& client_id, uint64_t request_id) {
  // A navigation accepted before this request must not start after it.
  if (navigator_ != nullptr) navigator_->Cancel();
  SetText(request.client_id, client_id.c_str());
  request.request_id = request_id;
  return controller_.Submit(request);
}

std::string RequestHandler::StatusText(const ControllerStatus& s) const {
  std::string text = std::string("mode ") + Name(s.mode);
  if (s.skill >= 0) {
    const std::string k = std::to_string(s.skill);
    text += s.mode == Mode::kStand ? " (skill " + k + " braking the last motion)" : " " + k;
  }
  text += ", t " + Seconds(s.time) + ", control " + (s.controller[0] != '\0' ? s.controller.data() : "free");
  text += ", faults " + (s.faults != 0 ? std::string(s.fault_message.data()) : std::string("none"));
  return text;
}

void RequestHandler::ShowStatus(const ControllerStatus& status) {
  std::lock_guard<std::mutex> lock(shown_mutex_);
  shown_ = status;
}

ControllerStatus RequestHandler::Shown() const {
  {
    std::lock_guard<std::mutex> lock(shown_mutex_);
    if (shown_) return *shown_;
  }
  return controller_.status();
}

}  // namespace flsd
