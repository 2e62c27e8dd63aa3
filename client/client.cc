#include "client/client.h"

#include <unistd.h>

#include <cstdio>
#include <random>

#include "comm/protocol.h"

namespace flsd {
namespace {

std::string MakeClientId() {
  char host[32] = {0};
  gethostname(host, sizeof host - 1);
  char id[64];
  std::snprintf(id, sizeof id, "%s-%d-%08x", host, static_cast<int>(getpid()),
                static_cast<unsigned>(std::random_device{}()));
  return id;
}

std::string Own(const char* s) { return s != nullptr ? s : ""; }

constexpr std::chrono::microseconds kSpin{1000};
// Long enough for a slow network and some clock skew between client and server (deadlines are
// wall-clock times), short enough to renew a lease of a second before it lapses.
constexpr std::chrono::milliseconds kHeartbeatTimeout{800};

}  // namespace

std::string CallResult::Describe() const {
  if (!answered) return "no reply from skilld";
  std::string text = std::string(dds::StatusName(status)) + ": " + message;
  if (!safety_report.empty()) text += " [safety: " + safety_report + "]";
  return text;
}

Client::Client(const Options& options)
    : id_(options.client_id.empty() ? MakeClientId() : options.client_id),
      options_(options),
      domain_(options.domain_id, options.partition, options.security),
      requests_(domain_, flsd_msgs_Request_desc, dds::kRequestTopic, dds::kRequestQos),
      states_(domain_, flsd_msgs_RobotState_desc, dds::kStateTopic, dds::kStateQos),
      wake_(domain_),
      reply_listener_(&Client::OnReplies, this),
      replies_(domain_, flsd_msgs_Reply_desc, dds::kReplyTopic, dds::kReplyQos, &reply_listener_) {
  if (domain_.secured()) {
    const std::string identity = domain_.identity();
    if (!options.client_id.empty() && options.client_id != identity) {
      throw dds::Error("client id '" + options.client_id + "' cannot be used with DDS Security: the server accepts only " +
                       "this participant's authenticated identity, " + identity);
    }
    id_ = identity;
  }
  // Request ids grow across client restarts with a fixed id, too: start from the wall clock.
  next_request_id_ = static_cast<uint64_t>(dds_time());
  background_ = std::thread([this] { Background(); });
}

Client::~Client() {
  running_ = false;
  wake_.Trigger();
  if (background_.joinable()) background_.join();
  if (in_control_) ReleaseControl(std::chrono::milliseconds(500));
  replies_.RemoveListener();  // before the members its callback uses are destroyed
}

bool Client::WaitForServer(std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < until) {
    // A round trip proves both directions are matched; until then a reply could be lost.
    if (requests_.matched_readers() > 0 && replies_.matched_writers() > 0 &&
        Call("status", {}, std::chrono::milliseconds(200)).answered) {
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

CallResult Client::Call(const std::string& call, const CallArgs& args, std::chrono::milliseconds timeout) {
  std::lock_guard<std::mutex> lock(call_mutex_);
  const uint64_t request_id = ++next_request_id_;
  flsd_msgs_Request request{};
  request.header.client_id = const_cast<char*>(id_.c_str());
  request.header.request_id = request_id;
  request.header.deadline_ns = dds_time() + std::chrono::duration_cast<std::chrono::nanoseconds>(timeout).count();
  request.call = const_cast<char*>(call.c_str());
  request.skill = args.skill;
  request.duration = args.duration;
  std::copy(args.velocity.begin(), args.velocity.end(), request.velocity);
  std::copy(args.goal.begin(), args.goal.end(), request.goal);
  request.map_yaml = const_cast<char*>(args.map_yaml.c_str());

  {
    std::lock_guard<std::mutex> reply_lock(reply_mutex_);
    awaited_request_id_ = request_id;
    awaited_result_ = CallResult{};
    reply_ready_ = false;
  }
  requests_.Write(request);
  // Spin briefly before sleeping: a reply usually comes within a few hundred microseconds, and
  // waking a sleeping thread can cost as much again on a virtual machine.
  const auto start = std::chrono::steady_clock::now();
  while (!reply_ready_.load(std::memory_order_acquire) &&
         std::chrono::steady_clock::now() - start < std::min<std::chrono::nanoseconds>(timeout, kSpin)) {
    std::this_thread::yield();
  }
  std::unique_lock<std::mutex> reply_lock(reply_mutex_);
  reply_arrived_.wait_until(reply_lock, start + timeout, [&] { return reply_ready_.load(); });
  awaited_request_id_ = 0;
  awaited_result_.request_id = request_id;
  return std::move(awaited_result_);
}

void Client::OnReplies(dds_entity_t reader, void* self) {
  auto* client = static_cast<Client*>(self);
  // Nothing may unwind into Cyclone's receive thread: it would end the process.
  try {
    client->TakeReplies(reader);
  } catch (...) {
  }
}

void Client::TakeReplies(dds_entity_t reader) {
  std::lock_guard<std::mutex> lock(reply_mutex_);
  // Replies to every client share the topic; keep only the answer to the call in flight. The
  // reader comes from Cyclone: the listener can fire before replies_ is fully constructed.
  dds::TakeSamples<flsd_msgs_Reply>(reader, [&](const flsd_msgs_Reply& reply, const dds_sample_info_t&) {
    if (awaited_request_id_ == 0 || reply.header.request_id != awaited_request_id_ || Own(reply.header.client_id) != id_) {
      return;
    }
    awaited_result_.answered = true;
    awaited_result_.status = reply.status;
    awaited_result_.message = Own(reply.message);
    awaited_result_.safety_report = Own(reply.safety_report);
    awaited_result_.skills.assign(reply.skills._buffer, reply.skills._buffer + reply.skills._length);
    reply_ready_.store(true, std::memory_order_release);
  }, 1 << 30);
  if (reply_ready_) reply_arrived_.notify_all();
}

CallResult Client::AcquireControl(std::chrono::milliseconds timeout) {
  CallResult r = Call("acquire_control", {}, timeout);
  if (r.ok()) {
    lost_control_ = false;
    in_control_ = true;
  }
  return r;
}

CallResult Client::ReleaseControl(std::chrono::milliseconds timeout) {
  in_control_ = false;
  return Call("release_control", {}, timeout);
}

std::optional<StateSample> Client::LatestState() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return latest_;
}

std::optional<StateSample> Client::WaitForState(const std::function<bool(const StateSample&)>& done,
                                                std::chrono::milliseconds timeout) const {
  std::unique_lock<std::mutex> lock(state_mutex_);
  std::optional<StateSample> found;
  state_arrived_.wait_for(lock, timeout, [&] {
    if (latest_ && done(*latest_)) found = latest_;
    return found.has_value();
  });
  return found;
}

void Client::Background() {
  auto next_heartbeat = std::chrono::steady_clock::now();
  while (running_) {
    states_.Wait(std::chrono::milliseconds(20), wake_.get());
    states_.Take([&](const flsd_msgs_RobotState& m, const dds_sample_info_t&) {
      StateSample s;
      s.msg = m;
      s.backend = Own(m.backend);
      s.fault_message = Own(m.fault_message);
      s.controller = Own(m.controller);
      s.task_client_id = Own(m.task.client_id);
      s.task_call = Own(m.task.call);
      s.task_message = Own(m.task.message);
      s.task_path.assign(m.task.path._buffer, m.task.path._buffer + m.task.path._length);
      s.msg.backend = s.msg.fault_message = s.msg.controller = nullptr;
      s.msg.task.client_id = s.msg.task.call = s.msg.task.message = nullptr;
      s.msg.task.path = {};
      {
        std::lock_guard<std::mutex> lock(state_mutex_);
        latest_ = std::move(s);
      }
      state_arrived_.notify_all();
    });
    const auto now = std::chrono::steady_clock::now();
    if (in_control_ && now >= next_heartbeat) {
      next_heartbeat = now + options_.heartbeat;
      // A slow or late heartbeat is not a lost lease; only the server saying so is.
      const CallResult r = Call("renew_control", {}, kHeartbeatTimeout);
      if (r.answered && r.status == flsd_msgs_STATUS_NOT_IN_CONTROL) {
        lost_control_ = true;
        in_control_ = false;
      }
    }
  }
}

}  // namespace flsd
