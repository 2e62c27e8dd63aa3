#include "client/client.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <random>

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
// Reports kept of this client's own tasks; a script waits on its few latest.
constexpr std::size_t kTrackedTasks = 32;

template <std::size_t N>
std::array<double, N> ToArray(const double (&values)[N]) {
  std::array<double, N> a;
  std::copy(values, values + N, a.begin());
  return a;
}

SkillInfo ToSkillInfo(const flsd_msgs_SkillInfo& m) {
  SkillInfo s;
  s.id = m.id;
  s.linear_velocity = ToArray(m.linear_velocity);
  s.angular_velocity = ToArray(m.angular_velocity);
  s.base_height = m.base_height;
  s.gait_frequency = m.gait_frequency;
  s.survival_steps = m.survival_steps;
  return s;
}

TaskReport ToTaskReport(const StateSample& s) {
  TaskReport t;
  t.client_id = s.task_client_id;
  t.request_id = s.msg.task.request_id;
  t.call = s.task_call;
  t.state = static_cast<TaskState>(s.msg.task.state);
  t.elapsed = s.msg.task.elapsed;
  t.remaining = s.msg.task.remaining;
  t.message = s.task_message;
  t.path = s.task_path;
  return t;
}

StateReport ToStateReport(const StateSample& s) {
  const flsd_msgs_RobotState& m = s.msg;
  StateReport r;
  r.time = m.time;
  r.tick = m.tick;
  r.backend = s.backend;
  r.mode = static_cast<Mode>(m.mode);
  r.skill = m.skill;
  r.position = ToArray(m.position);
  r.orientation = ToArray(m.orientation);
  r.linear_velocity = ToArray(m.linear_velocity);
  r.angular_velocity = ToArray(m.angular_velocity);
  r.joint_position = ToArray(m.joint_position);
  r.joint_velocity = ToArray(m.joint_velocity);
  r.joint_torque = ToArray(m.joint_torque);
  std::copy(m.foot_contact, m.foot_contact + 4, r.foot_contact.begin());
  r.faults = m.faults;
  r.fault_message = s.fault_message;
  r.controller = s.controller;
  r.deadline_misses = m.deadline_misses;
  r.requests_dropped = m.requests_dropped;
  r.task = ToTaskReport(s);
  return r;
}

}  // namespace

Reply CallResult::reply() const {
  Reply r;
  r.request_id = request_id;
  r.status = answered ? static_cast<ReplyStatus>(status) : ReplyStatus::kNoReply;
  r.message = message;
  r.safety_report = safety_report;
  return r;
}

Client::Client(const Options& options)
    : id_(options.client_id.empty() ? MakeClientId() : options.client_id),
      options_(options),
      domain_(options.domain_id, options.partition, options.security),
      states_(domain_, flsd_msgs_RobotState_desc, dds::kStateTopic, dds::kStateQos),
      wake_(domain_),
      reply_listener_(&Client::OnReplies, this) {
  if (!options.read_only) {
    requests_.emplace(domain_, flsd_msgs_Request_desc, dds::kRequestTopic, dds::kRequestQos);
    replies_.emplace(domain_, flsd_msgs_Reply_desc, dds::kReplyTopic, dds::kReplyQos, &reply_listener_);
  }
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
  if (replies_) replies_->RemoveListener();  // before the members its callback uses are destroyed
}

bool Client::WaitForServer(std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < until) {
    // A round trip proves both directions are matched; until then a reply could be lost.
    if (requests_ && requests_->matched_readers() > 0 && replies_->matched_writers() > 0 &&
        Call(flsd::CallName(flsd::Call::kStatus), {}, std::chrono::milliseconds(200)).answered) {
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

CallResult Client::Call(const std::string& call, const CallArgs& args, std::chrono::milliseconds timeout) {
  std::lock_guard<std::mutex> lock(call_mutex_);
  CallResult result = Send(call, args, timeout);
  if (!unreported_safety_.empty()) {
    result.safety_report = unreported_safety_ + (result.safety_report.empty() ? "" : "; " + result.safety_report);
    unreported_safety_.clear();
  }
  return result;
}

CallResult Client::Send(const std::string& call, const CallArgs& args, std::chrono::milliseconds timeout) {
  const uint64_t request_id = ++next_request_id_;
  if (!requests_) {
    CallResult unsent;
    unsent.request_id = request_id;
    unsent.message = "not sent: this client reads the state only";
    return unsent;
  }
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
  requests_->Write(request);
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

Reply Client::Simple(flsd::Call call, std::chrono::milliseconds timeout) {
  return Call(flsd::CallName(call), {}, timeout).reply();
}

Task Client::Long(flsd::Call call, const CallArgs& args, std::chrono::milliseconds timeout) {
  return Task(*this, Call(flsd::CallName(call), args, timeout).reply());
}

std::vector<SkillInfo> Client::ListSkills(std::chrono::milliseconds timeout) {
  const CallResult r = Call(flsd::CallName(flsd::Call::kListSkills), {}, timeout);
  if (!r.ok()) throw CallError(r.reply());
  std::vector<SkillInfo> skills;
  for (const flsd_msgs_SkillInfo& s : r.skills) skills.push_back(ToSkillInfo(s));
  return skills;
}

Reply Client::Status(std::chrono::milliseconds timeout) { return Simple(flsd::Call::kStatus, timeout); }

Task Client::ExecuteSkill(int skill, double duration, std::chrono::milliseconds timeout) {
  CallArgs args;
  args.skill = skill;
  args.duration = duration;
  return Long(flsd::Call::kExecuteSkill, args, timeout);
}

Task Client::TrackVelocity(double vx, double vy, double wz, double duration, std::chrono::milliseconds timeout) {
  CallArgs args;
  args.velocity = {vx, vy, wz};
  args.duration = duration;
  return Long(flsd::Call::kTrackVelocity, args, timeout);
}

Task Client::Navigate(double x, double y, const std::string& map_yaml, double duration,
                      std::chrono::milliseconds timeout) {
  CallArgs args;
  args.goal = {x, y};
  args.map_yaml = map_yaml;
  args.duration = duration;
  return Long(flsd::Call::kNavigate, args, timeout);
}

Reply Client::Stop(std::chrono::milliseconds timeout) { return Simple(flsd::Call::kStop, timeout); }
Reply Client::Stand(std::chrono::milliseconds timeout) { return Simple(flsd::Call::kStand, timeout); }
Reply Client::Reset(std::chrono::milliseconds timeout) { return Simple(flsd::Call::kReset, timeout); }
Reply Client::Damp(std::chrono::milliseconds timeout) { return Simple(flsd::Call::kDamp, timeout); }
Reply Client::ClearStop(std::chrono::milliseconds timeout) { return Simple(flsd::Call::kClearStop, timeout); }

Reply Client::AcquireControl(std::chrono::milliseconds timeout) {
  Reply r = Simple(flsd::Call::kAcquireControl, timeout);
  if (r.ok()) {
    lost_control_ = false;
    in_control_ = true;
  }
  return r;
}

Reply Client::ReleaseControl(std::chrono::milliseconds timeout) {
  in_control_ = false;
  return Simple(flsd::Call::kReleaseControl, timeout);
}

std::optional<StateReport> Client::State() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  if (!latest_) return std::nullopt;
  return ToStateReport(*latest_);
}

std::optional<StateReport> Client::NextState(uint64_t after, std::chrono::milliseconds timeout) const {
  const std::optional<StateSample> s =
      WaitForState([after](const StateSample& sample) { return sample.msg.tick > after; }, timeout);
  if (!s) return std::nullopt;
  return ToStateReport(*s);
}

TaskReport Client::TaskProgress(uint64_t request_id) const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  const auto it = tasks_.find(request_id);
  if (it != tasks_.end()) return it->second;
  TaskReport none;
  none.client_id = id_;
  none.request_id = request_id;
  return none;
}

bool Client::WaitForTask(uint64_t request_id, std::chrono::milliseconds timeout) const {
  std::unique_lock<std::mutex> lock(state_mutex_);
  return state_arrived_.wait_for(lock, timeout, [&] {
    const auto it = tasks_.find(request_id);
    return it != tasks_.end() && it->second.ended();
  });
}

void Client::TrackTasks(const StateSample& sample) {
  const bool ours = sample.task_client_id == id_;
  const uint64_t current = sample.msg.task.request_id;
  // The state topic carries one task, the last: one of ours still running that it no longer
  // names was ended by the call that replaced it.
  for (auto& [request_id, report] : tasks_) {
    if (report.state == TaskState::kRunning && !(ours && request_id == current)) {
      report.state = TaskState::kPreempted;
      report.message = "replaced by " + std::string(sample.task_call) + " from " + sample.task_client_id;
    }
  }
  if (!ours) return;
  tasks_[current] = ToTaskReport(sample);
  if (tasks_.size() > kTrackedTasks) tasks_.erase(tasks_.begin());
}

TaskReport Task::Progress() const { return client_->TaskProgress(request_id()); }

bool Task::Done() const { return !accepted() || Progress().ended(); }

bool Task::Wait(std::chrono::milliseconds timeout) const {
  return !accepted() || client_->WaitForTask(request_id(), timeout);
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
        TrackTasks(s);
        latest_ = std::move(s);
      }
      state_arrived_.notify_all();
    });
    const auto now = std::chrono::steady_clock::now();
    if (in_control_ && now >= next_heartbeat) {
      next_heartbeat = now + options_.heartbeat;
      // A slow or late heartbeat is not a lost lease; only the server saying so is.
      std::unique_lock<std::mutex> lock(call_mutex_);
      const CallResult r = Send(flsd::CallName(flsd::Call::kRenewControl), {}, kHeartbeatTimeout);
      if (!r.safety_report.empty()) {
        unreported_safety_ += (unreported_safety_.empty() ? "" : "; ") + r.safety_report;
      }
      lock.unlock();
      if (r.answered && r.status == flsd_msgs_STATUS_NOT_IN_CONTROL) {
        lost_control_ = true;
        in_control_ = false;
      }
    }
  }
}

}  // namespace flsd
