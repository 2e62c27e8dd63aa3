#include "server/request_handler.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "comm/protocol.h"
#include "core/check.h"

namespace flsd {
namespace {

constexpr const char* kKnownCalls =
    "list_skills, status, execute_skill, track_velocity, navigate, stop, stand, damp, acquire_control, "
    "renew_control, release_control, reset";

ReplyContent Reply(flsd_msgs_ReplyStatus status, std::string message) {
  ReplyContent r;
  r.status = status;
  r.message = std::move(message);
  return r;
}

bool AllFinite(const double* values, int n) {
  return std::all_of(values, values + n, [](double v) { return std::isfinite(v); });
}

std::string Seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f s", s);
  return text;
}

// Empty if `duration` is in (0, max].
std::string DurationError(double duration, double max) {
  if (std::isfinite(duration) && duration > 0.0 && duration <= max) return "";
  return "duration must be in (0, " + Seconds(max) + "], got " + std::to_string(duration);
}

}  // namespace

RequestHandler::RequestHandler(Controller& controller, const ServerConfig& config, Navigator* navigator)
    : controller_(controller), config_(config), navigator_(navigator), lease_(config.lease_timeout) {
  if (!config.navigation.map.empty()) default_map_ = Map2D::Load(config.navigation.map);
}

RequestHandler::ClientState& RequestHandler::Client(const std::string& id, double now) {
  auto it = clients_.find(id);
  if (it == clients_.end()) {
    if (clients_.size() >= kMaxClients) {  // forget the longest-silent client
      auto oldest = std::min_element(clients_.begin(), clients_.end(), [](const auto& a, const auto& b) {
        return a.second.last_seen < b.second.last_seen;
      });
      clients_.erase(oldest);
    }
    ClientState fresh;
    fresh.tokens = config_.request_burst;
    fresh.last_seen = now;
    fresh.reported_trips = controller_.status().safety_trips;  // a newcomer hears of trips to come
    it = clients_.emplace(id, fresh).first;
  }
  return it->second;
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
    ControlRequest stop;
    stop.kind = ControlRequest::Kind::kStop;
    stop.stop_state = flsd_msgs_TASK_LEASE_LOST;
    SetText(stop.reason, ("control lease of " + holder + " lapsed after " + Seconds(lease_.timeout()) +
                          " without a request; standing")
                             .c_str());
    controller_.SubmitUrgent(stop);
  }
}

std::optional<ReplyContent> RequestHandler::Handle(const flsd_msgs_Request& request, double now, int64_t wall_ns) {
  Poll(now);
  const std::string client_id = request.header.client_id != nullptr ? request.header.client_id : "";
  if (client_id.empty() || client_id.size() > kMaxClientIdLength) {
    return Reply(flsd_msgs_STATUS_INVALID_ARGUMENT,
                 "client_id must have 1 to " + std::to_string(kMaxClientIdLength) + " characters");
  }
  ClientState& client = Client(client_id, now);
  if (!TakeToken(client, now)) {
    ++dropped_;
    return std::nullopt;
  }
  const uint64_t id = request.header.request_id;
  if (client.seen_request && id <= client.last_request_id) {
    return Reply(flsd_msgs_STATUS_DUPLICATE, "request_id " + std::to_string(id) + " is not above " +
                                                 std::to_string(client.last_request_id) +
                                                 ", the last one from this client; not executed");
  }
  client.seen_request = true;
  client.last_request_id = id;
  if (request.header.deadline_ns != 0 && wall_ns > request.header.deadline_ns) {
    return Reply(flsd_msgs_STATUS_DEADLINE_EXCEEDED,
                 "arrived " + Seconds(static_cast<double>(wall_ns - request.header.deadline_ns) * 1e-9) +
                     " after its deadline; not executed");
  }

  ReplyContent reply = Dispatch(request, client_id, now);
  const ControllerStatus status = controller_.status();
  if (status.safety_trips > client.reported_trips) {
    reply.safety_report = status.fault_message[0] != '\0' ? status.fault_message.data() : "safety stop";
    client.reported_trips = status.safety_trips;
  }
  return reply;
}

ReplyContent RequestHandler::Dispatch(const flsd_msgs_Request& request, const std::string& client_id, double now) {
  const std::string call = request.call != nullptr ? request.call : "";
  if (call == "list_skills") {
    ReplyContent r = Reply(flsd_msgs_STATUS_OK, std::to_string(controller_.library().num_skills()) + " skills");
    r.with_skills = true;
    return r;
  }
  if (call == "status") return Reply(flsd_msgs_STATUS_OK, StatusText(controller_.status()));
  if (call == "acquire_control") {
    if (!lease_.Acquire(client_id, now)) {
      return Reply(flsd_msgs_STATUS_NOT_IN_CONTROL, "control is held by " + lease_.holder());
    }
    return Reply(flsd_msgs_STATUS_OK, "control granted; it lapses after " + Seconds(lease_.timeout()) +
                                          " without a request from this client");
  }
  if (call == "renew_control") {  // a heartbeat: never grants a lease that is not held
    if (!lease_.Renew(client_id, now)) {
      return Reply(flsd_msgs_STATUS_NOT_IN_CONTROL, lease_.held() ? "control is held by " + lease_.holder()
                                                                  : std::string("this client does not hold control"));
    }
    return Reply(flsd_msgs_STATUS_OK, "control renewed");
  }
  if (call == "release_control") {
    if (!lease_.Release(client_id)) {
      return Reply(flsd_msgs_STATUS_NOT_IN_CONTROL, "this client does not hold control");
    }
    ControlRequest stop;
    stop.kind = ControlRequest::Kind::kStop;
    SetText(stop.reason, "control released");
    SetText(stop.client_id, client_id.c_str());
    stop.request_id = request.header.request_id;
    controller_.SubmitUrgent(stop);  // never lost to a full queue: nobody holds control now
    return Reply(flsd_msgs_STATUS_OK, "control released; the robot stands");
  }
  if (call == "damp") {  // the emergency stop: anyone may press it
    ControlRequest damp;
    damp.kind = ControlRequest::Kind::kDamp;
    SetText(damp.reason, ("emergency stop from " + client_id).c_str());
    SetText(damp.client_id, client_id.c_str());
    damp.request_id = request.header.request_id;
    controller_.SubmitUrgent(damp);
    return Reply(flsd_msgs_STATUS_OK, "damping; call stand to recover");
  }
  static const char* const kMotionCalls[] = {"execute_skill", "track_velocity", "navigate", "stop", "stand", "reset"};
  if (std::find_if(std::begin(kMotionCalls), std::end(kMotionCalls), [&](const char* c) { return call == c; }) !=
      std::end(kMotionCalls)) {
    if (!lease_.Renew(client_id, now)) {
      return Reply(flsd_msgs_STATUS_NOT_IN_CONTROL,
                   lease_.held() ? "control is held by " + lease_.holder()
                                 : std::string("no client holds control; call acquire_control first"));
    }
    return Motion(request, client_id, now);
  }
  return Reply(flsd_msgs_STATUS_UNKNOWN_CALL, "unknown call '" + call + "'; known calls: " + kKnownCalls);
}

ReplyContent RequestHandler::Motion(const flsd_msgs_Request& request, const std::string& client_id, double now) {
  const std::string call = request.call;
  const ControllerStatus status = controller_.status();
  ControlRequest control;
  if (call == "execute_skill") {
    const int k = request.skill;
    if (k < 0 || k >= controller_.library().num_skills()) {
      return Reply(flsd_msgs_STATUS_INVALID_ARGUMENT, "skill " + std::to_string(k) + " is not in [0, " +
                                                          std::to_string(controller_.library().num_skills()) + ")");
    }
    if (const std::string why = DurationError(request.duration, config_.max_duration); !why.empty()) {
      return Reply(flsd_msgs_STATUS_INVALID_ARGUMENT, why);
    }
    const SkillDescriptor& skill = controller_.library().skills()[k];
    if (skill.fell && skill.survival_steps < config_.safety.min_skill_survival) {
      return Reply(flsd_msgs_STATUS_NOT_AVAILABLE,
                   "skill " + std::to_string(k) + " fell after " + std::to_string(skill.survival_steps) +
                       " steps in the library's evaluation (fewer than safety.min_skill_survival = " +
                       std::to_string(config_.safety.min_skill_survival) + "); it is not run");
    }
    if (const std::string blocked = MotionBlocked(status); !blocked.empty()) {
      return Reply(flsd_msgs_STATUS_SAFETY_STOP, blocked);
    }
    control.kind = ControlRequest::Kind::kSkill;
    control.skill = k;
    control.duration = request.duration;
    if (!Submit(control, client_id, request.header.request_id)) {
      return Reply(flsd_msgs_STATUS_INTERNAL, "the control queue is full; retry");
    }
    return Reply(flsd_msgs_STATUS_OK, "skill " + std::to_string(k) + " for " + Seconds(request.duration) +
                                          " accepted; progress is on the state topic");
  }
  if (call == "track_velocity" || call == "navigate") return Velocity(request, client_id);
  if (call == "reset" && !controller_.backend_can_reset()) {
    return Reply(flsd_msgs_STATUS_NOT_AVAILABLE, "this backend cannot reset the robot; stand it up by hand");
  }
  if (call == "stand" && status.hazards != 0) {
    // Standing clears a latched stop, but only once the robot is upright, in range and sensed.
    char text[192];
    DescribeFaults(status.hazards, status.state, config_.safety, text, sizeof text, status.backend_fault.data());
    return Reply(flsd_msgs_STATUS_SAFETY_STOP, std::string("cannot stand: ") + text +
                                                   (controller_.backend_can_reset() ? "; call reset" : "; put the robot upright"));
  }
  control.kind = call == "stand" ? ControlRequest::Kind::kStand
                 : call == "stop" ? ControlRequest::Kind::kStop
                                  : ControlRequest::Kind::kReset;
  SetText(control.reason, ("stopped by " + client_id).c_str());
  if (!Submit(control, client_id, request.header.request_id)) {
    return Reply(flsd_msgs_STATUS_INTERNAL, "the control queue is full; retry");
  }
  return Reply(flsd_msgs_STATUS_OK, call == "stand" ? "standing" : call == "stop" ? "stopping; the robot stands" : "reset");
}

std::string RequestHandler::MotionBlocked(const ControllerStatus& status) const {
  if (status.faults != 0) {
    return std::string("a safety stop is latched (") + status.fault_message.data() + "); call stand first";
  }
  if (status.hazards != 0) {
    char text[192];
    DescribeFaults(status.hazards, status.state, config_.safety, text, sizeof text, status.backend_fault.data());
    return std::string("cannot start moving: ") + text;
  }
  return "";
}

ReplyContent RequestHandler::Velocity(const flsd_msgs_Request& request, const std::string& client_id) {
  const std::string call = request.call;
  if (!controller_.has_selector()) {
    return Reply(flsd_msgs_STATUS_NOT_AVAILABLE, call + " is not available: the skill library " +
                                                     controller_.library().path() +
                                                     " has no skill selector (flsd export-selector adds one)");
  }
  ControlRequest control;
  control.kind = ControlRequest::Kind::kVelocity;
  std::string accepted;
  std::optional<NavigationJob> job;
  if (call == "track_velocity") {
    if (!AllFinite(request.velocity, 3)) return Reply(flsd_msgs_STATUS_INVALID_ARGUMENT, "velocity must be finite");
    if (const std::string why = DurationError(request.duration, config_.max_duration); !why.empty()) {
      return Reply(flsd_msgs_STATUS_INVALID_ARGUMENT, why);
    }
    std::copy(request.velocity, request.velocity + 3, control.velocity.begin());
    control.duration = request.duration;
    const SelectorNetwork& selector = *controller_.library().selector();
    char text[256];
    std::snprintf(text, sizeof text, "velocity (%.2f m/s, %.2f m/s, %.2f rad/s) for %s accepted", control.velocity[0],
                  control.velocity[1], control.velocity[2], Seconds(request.duration).c_str());
    accepted = text;
    for (int a = 0; a < 3; ++a) {
      const double clipped = std::clamp(control.velocity[a], selector.command_min[a], selector.command_max[a]);
      if (clipped != control.velocity[a]) {
        static const char* const kAxes[] = {"vx", "vy", "wz"};
        std::snprintf(text, sizeof text, "; %s clipped to %.2f, the edge of the trained range [%.2f, %.2f]", kAxes[a],
                      clipped, selector.command_min[a], selector.command_max[a]);
        accepted += text;
      }
    }
    const std::array<double, 3> seen = ClipCommand(selector, control.velocity.data());
    if (seen[0] == 0.0 && seen[1] == 0.0 && (control.velocity[0] != 0.0 || control.velocity[1] != 0.0)) {
      std::snprintf(text, sizeof text, "; vx and vy zeroed: slower than %.2f m/s, as in training", selector.min_planar_speed);
      accepted += text;
    }
  } else {
    if (!AllFinite(request.goal, 2)) return Reply(flsd_msgs_STATUS_INVALID_ARGUMENT, "goal must be finite");
    if (navigator_ == nullptr) return Reply(flsd_msgs_STATUS_NOT_AVAILABLE, "navigate is not available on this server");
    job.emplace();
    job->goal = Eigen::Vector2d(request.goal[0], request.goal[1]);
    const std::string map_yaml = request.map_yaml != nullptr ? request.map_yaml : "";
    if (!map_yaml.empty()) {
      try {
        job->map = Map2D::Parse(map_yaml, "the request's map");
      } catch (const InputError& e) {
        return Reply(flsd_msgs_STATUS_INVALID_ARGUMENT, e.what());
      }
    } else if (default_map_) {
      job->map = *default_map_;
    } else {
      return Reply(flsd_msgs_STATUS_INVALID_ARGUMENT,
                   "no map: send one with the request, or name one in the server config (navigation.map)");
    }
    // A duration, if given, bounds this navigation; otherwise the server's navigation.timeout.
    job->timeout = config_.navigation.timeout;
    if (request.duration != 0.0) {
      if (const std::string why = DurationError(request.duration, config_.max_duration); !why.empty()) {
        return Reply(flsd_msgs_STATUS_INVALID_ARGUMENT, why);
      }
      job->timeout = request.duration;
    }
    control.navigate = true;
    control.duration = job->timeout + 1.0;  // the navigator times out first, with a message
    char text[192];
    std::snprintf(text, sizeof text, "navigation to (%.2f, %.2f) accepted; planning", job->goal.x(), job->goal.y());
    accepted = text;
  }
  if (const std::string blocked = MotionBlocked(controller_.status()); !blocked.empty()) {
    return Reply(flsd_msgs_STATUS_SAFETY_STOP, blocked);
  }
  if (!Submit(control, client_id, request.header.request_id)) {
    return Reply(flsd_msgs_STATUS_INTERNAL, "the control queue is full; retry");
  }
  if (job) {
    SetText(job->client_id, client_id.c_str());
    job->request_id = request.header.request_id;
    navigator_->Start(std::move(*job));
  }
  return Reply(flsd_msgs_STATUS_OK, accepted + "; progress is on the state topic");
}

bool RequestHandler::Submit(ControlRequest request, const std::string& client_id, uint64_t request_id) {
  SetText(request.client_id, client_id.c_str());
  request.request_id = request_id;
  return controller_.Submit(request);
}

std::string RequestHandler::StatusText(const ControllerStatus& s) const {
  std::string text = std::string("mode ") + dds::ModeName(s.mode);
  if (s.skill >= 0) text += " " + std::to_string(s.skill);
  text += ", t " + Seconds(s.time) + ", control " + (lease_.held() ? lease_.holder() : std::string("free"));
  text += ", faults " + (s.faults != 0 ? std::string(s.fault_message.data()) : std::string("none"));
  return text;
}

}  // namespace flsd
