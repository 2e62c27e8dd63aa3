#include "server/dds_service.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iterator>

#include "comm/protocol.h"

namespace flsd {
namespace {

double MonotonicSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

char* Text(const std::string& s) { return const_cast<char*>(s.c_str()); }  // Cyclone only reads it

std::vector<flsd_msgs_SkillInfo> MakeSkillInfos(const SkillLibrary& library) {
  std::vector<flsd_msgs_SkillInfo> infos;
  for (const SkillDescriptor& d : library.skills()) {
    flsd_msgs_SkillInfo info{};
    info.id = d.id;
    for (int i = 0; i < 3; ++i) {
      info.linear_velocity[i] = d.mean_linear_velocity[i];
      info.angular_velocity[i] = d.mean_angular_velocity[i];
    }
    info.base_height = d.mean_base_height;
    info.gait_frequency = d.gait_frequency_hz;
    const std::optional<SkillFall> fall = EarliestFall(d);
    info.survival_steps = fall ? fall->steps : d.survival_steps;
    infos.push_back(info);
  }
  return infos;
}

}  // namespace

DdsService::DdsService(const ServerConfig& config, Controller& controller, const ControlLoop& loop,
                       std::string backend_name)
    : controller_(controller),
      loop_(loop),
      backend_name_(std::move(backend_name)),
      domain_(config.domain_id, config.partition, config.security),
      replies_(domain_, flsd_msgs_Reply_desc, dds::kReplyTopic, dds::kReplyQos),
      states_(domain_, flsd_msgs_RobotState_desc, dds::kStateTopic, dds::kStateQos),
      navigator_(controller.selector(true) ? std::make_unique<Navigator>(controller, config.navigation) : nullptr),
      handler_(controller, config, navigator_.get()),
      audit_(config.audit_log, config.audit_certificates),
      skills_(MakeSkillInfos(controller.library())),
      listener_(&DdsService::OnRequests, this),
      requests_(domain_, flsd_msgs_Request_desc, dds::kRequestTopic, dds::kRequestQos, &listener_) {}

void DdsService::Start() {
  if (domain_.secured()) {
    spdlog::info("DDS Security on: skilld is {}; a request runs only under its writer's identity", domain_.identity());
  }
  running_ = true;
  ServeRequests();  // any that came before
  poll_thread_ = std::thread([this] { PollLeases(); });
  state_thread_ = std::thread([this] { PublishState(); });
}

void DdsService::Stop() {
  requests_.RemoveListener();  // waits for a callback in progress; none starts after it
  if (!running_.exchange(false)) return;
  poll_wake_.notify_all();
  if (poll_thread_.joinable()) poll_thread_.join();
  if (state_thread_.joinable()) state_thread_.join();
}

void DdsService::OnRequests(dds_entity_t, void* self) {
  auto* service = static_cast<DdsService*>(self);
  // Nothing may unwind into Cyclone's receive thread: it would end the process.
  try {
    if (service->running_) service->ServeRequests();
  } catch (const std::exception& e) {
    spdlog::error("serving requests failed: {}", e.what());
  } catch (...) {
    spdlog::error("serving requests failed");
  }
}

void DdsService::PollLeases() {
  std::unique_lock<std::mutex> lock(poll_mutex_);
  while (running_) {
    poll_wake_.wait_for(lock, std::chrono::milliseconds(20));
    std::lock_guard<std::mutex> handler_lock(handler_mutex_);
    handler_.Poll(MonotonicSeconds());
  }
}

void DdsService::ServeRequests() {
  std::lock_guard<std::mutex> lock(handler_mutex_);
  requests_.Take([&](const flsd_msgs_Request& request, const dds_sample_info_t& info) {
    const std::string client_id = request.header.client_id != nullptr ? request.header.client_id : "";
    const uint64_t request_id = request.header.request_id;
    const int64_t deadline_ns = request.header.deadline_ns;
    const std::string& identity = domain_.secured() ? IdentityOf(info.publication_handle) : client_id;
    // Empty: not a call the audit log records.
    const std::string audited =
        AuditLog::Audited(request.call)
            ? audit_.Describe(!domain_.secured() ? "" : identity.empty() ? "unmatched" : identity, request)
            : "";
    try {
      const DeferredReply send = [this, client_id, request_id, deadline_ns, audited](const ReplyContent& content) {
        SendReply(client_id, request_id, deadline_ns, content);
        if (!audited.empty()) audit_.Record(audited, content);
      };
      const DeferredReply later = [this, send](const ReplyContent& content) { Answer(content, send); };
      std::optional<ReplyContent> reply;
      if (client_id != identity) {
        // Before the handler: an impostor must not touch the lease, nor the ids and rate of the client it names.
        reply.emplace();
        reply->status = ReplyStatus::kInvalidArgument;
        reply->message = "client_id '" + client_id + "' is not the authenticated identity of its writer (" +
                         (identity.empty() ? std::string("no longer matched") : identity) +
                         "); with DDS Security a client's id is its participant's identity; not executed";
      } else {
        reply = handler_.Handle(request, MonotonicSeconds(), dds_time(), later);
      }
      if (reply) later(*reply);
    } catch (const std::exception& e) {
      // Nothing a client sends may stop the server; say what went wrong instead.
      spdlog::error("request '{}' from '{}' failed: {}", request.call ? request.call : "",
                    request.header.client_id ? request.header.client_id : "", e.what());
      ReplyContent internal;
      internal.status = ReplyStatus::kInternal;
      internal.message = e.what();
      SendReply(client_id, request_id, deadline_ns, internal);
    }
  }, 1 << 30);
  dropped_ = handler_.dropped();
}

const std::string& DdsService::IdentityOf(dds_instance_handle_t publication) {
  auto it = identities_.find(publication);
  if (it != identities_.end()) return it->second;
  if (identities_.size() >= 1024) identities_.clear();  // writers come and go; looking one up again is cheap
  std::string identity = dds::WriterIdentity(requests_.get(), publication);
  if (identity.empty()) {  // gone already: refuse this sample, but look again next time
    static const std::string kNone;
    return kNone;
  }
  return identities_.emplace(publication, std::move(identity)).first->second;
}

void DdsService::SendReply(const std::string& client_id, uint64_t request_id, int64_t deadline_ns,
                           const ReplyContent& content) {
  flsd_msgs_Reply reply{};
  reply.header.client_id = Text(client_id);
  reply.header.request_id = request_id;
  reply.header.deadline_ns = deadline_ns;
  reply.status = dds::ToIdl(content.status);
  reply.message = Text(content.message);
  reply.safety_report = Text(content.safety_report);
  if (content.with_skills) {
    reply.skills._buffer = skills_.data();
    reply.skills._length = reply.skills._maximum = static_cast<uint32_t>(skills_.size());
  }
  try {
    replies_.Write(reply);
    ++replies_sent_;
  } catch (const dds::Error& e) {
    spdlog::warn("reply to '{}' request {} not sent: {}", reply.header.client_id, reply.header.request_id, e.what());
  }
}

void DdsService::Answer(const ReplyContent& content, const DeferredReply& send) {
  if (content.ticket == 0) return send(content);
  std::lock_guard<std::mutex> lock(waiting_mutex_);
  waiting_.push_back({content, send, MonotonicSeconds() + kApplyTimeout});
}

void DdsService::AnswerApplied(const ControllerStatus& status) {
  const uint64_t applied = status.applied;
  std::vector<WaitingReply> due;
  {
    std::lock_guard<std::mutex> lock(waiting_mutex_);
    if (waiting_.empty()) return;
    const double now = MonotonicSeconds();
    const auto waits = std::stable_partition(waiting_.begin(), waiting_.end(), [&](const WaitingReply& w) {
      return w.content.ticket > applied && now < w.give_up;
    });
    due.assign(std::make_move_iterator(waits), std::make_move_iterator(waiting_.end()));
    waiting_.erase(waits, waiting_.end());
  }
  // Sent without the lock: the request thread must never wait for a DDS write here.
  for (WaitingReply& w : due) {
    if (w.content.ticket > applied) {
      char text[128];
      std::snprintf(text, sizeof text, "the control loop has not applied the request in %.1f s; it may yet: "
                    "call status before retrying", kApplyTimeout);
      w.content.status = ReplyStatus::kInternal;
      w.content.message = text;
    } else if (w.content.settle) {
      w.content.settle(w.content, status);
    }
    w.send(w.content);
  }
}

void DdsService::PublishState() {
  ControllerStatus s;
  uint64_t last_tick = controller_.status().tick;
  while (running_) {
    if (!controller_.WaitForTickAfter(last_tick, std::chrono::milliseconds(100), s)) {
      AnswerApplied(s);  // nothing newer applied: those waiting too long time out
      continue;
    }
    last_tick = s.tick;
    flsd_msgs_RobotState m{};
    m.time = s.time;
    m.tick = s.tick;
    m.backend = Text(backend_name_);
    m.mode = dds::ToIdl(s.mode);
    m.skill = s.skill;
    const RobotState& r = s.state;
    for (int i = 0; i < 3; ++i) {
      m.position[i] = r.base_position[i];
      m.linear_velocity[i] = r.base_linear_velocity[i];
      m.angular_velocity[i] = r.base_angular_velocity[i];
    }
    m.orientation[0] = r.base_orientation.w();
    m.orientation[1] = r.base_orientation.x();
    m.orientation[2] = r.base_orientation.y();
    m.orientation[3] = r.base_orientation.z();
    std::copy(r.joint_position.begin(), r.joint_position.end(), m.joint_position);
    std::copy(r.joint_velocity.begin(), r.joint_velocity.end(), m.joint_velocity);
    std::copy(r.joint_torque.begin(), r.joint_torque.end(), m.joint_torque);
    std::copy(r.foot_contact.begin(), r.foot_contact.end(), m.foot_contact);
    m.faults = s.faults;
    m.fault_message = s.fault_message.data();
    m.controller = s.controller.data();
    m.deadline_misses = loop_.deadline_misses();
    m.requests_dropped = dropped_.load();
    m.task.client_id = s.task.client_id.data();
    m.task.request_id = s.task.request_id;
    m.task.call = s.task.call.data();
    m.task.state = dds::ToIdl(s.task.state);
    m.task.elapsed = s.task.elapsed;
    m.task.remaining = s.task.remaining;
    m.task.message = s.task.message.data();
    std::vector<double> path;
    if (navigator_ && std::string(s.task.call.data()) == CallName(Call::kNavigate)) path = navigator_->Path();
    m.task.path._buffer = path.data();
    m.task.path._length = m.task.path._maximum = static_cast<uint32_t>(path.size());
    m.task.path._release = false;
    try {
      states_.Write(m);
    } catch (const dds::Error& e) {
      spdlog::warn("state sample not sent: {}", e.what());
    }
    handler_.ShowStatus(s);  // replies sent at once now say what the topic shows
    AnswerApplied(s);        // after the sample of the tick that applied them
  }
}

}  // namespace flsd
