#include "server/controller.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "comm/protocol.h"

namespace flsd {
namespace {

int Ticks(double seconds) { return static_cast<int>(std::lround(seconds / a1::kControlDt)); }

// Legs folded and spread, as the A1 lies after its motors go slack: a recovery lies down in this
// pose, so that the robot rests on its belly with its feet wide, then stands up from it. (From
// legs folded under the body, the rising robot pins its feet too close and stands pitched.)
constexpr a1::JointArray<double> kLyingPose = {-0.45, 1.1, -2.6, 0.45, 1.1, -2.6, -0.45, 1.45, -2.6, 0.45, 1.45, -2.6};

// The selector `selector` names, or none: "learned" over a library without a selector, or "auto"
// over one without a selector or a surviving skill, leaves the calls it serves unavailable. "auto"
// without a learned selector is `analytic`.
std::optional<HierarchicalPolicy> MakeHierarchy(const SkillLibrary& library, const char* key,
                                                const std::string& selector, SelectorKind analytic) {
  const bool learned = selector == "learned" || (selector == "auto" && library.selector());
  if (learned) {
    return library.selector() ? std::optional<HierarchicalPolicy>(std::in_place, library) : std::nullopt;
  }
  if (selector == "auto") {
    try {
      return std::optional<HierarchicalPolicy>(std::in_place, library, analytic);
    } catch (const InputError&) {
      return std::nullopt;
    }
  }
  try {
    return std::optional<HierarchicalPolicy>(std::in_place, library, ParseSelectorKind(selector));
  } catch (const InputError& e) {
    throw InputError(std::string("server config ") + key + ": " + e.what());
  }
}

}  // namespace

Controller::Controller(Backend& backend, const SkillLibrary& library, const ServerConfig& config)
    : backend_(backend),
      library_(library),
      config_(config),
      supervisor_(config.safety),
      runner_(library),
      velocity_selector_(MakeHierarchy(library, "selector", config.selector, SelectorKind::kTimeSharing)),
      navigation_selector_(
          MakeHierarchy(library, "navigation.selector", config.navigation.selector, SelectorKind::kNearestSkill)),
      target_filter_(library.action_filter_hz(), library.action_filter_order()) {
  try {
    still_skills_.emplace(library);
  } catch (const InputError&) {  // no dependable skill: the stand follows a policy at once
  }
  state_ = backend_.Read();
  Publish();
}

HierarchicalPolicy* Controller::Hierarchy(Mode mode) {
  if (mode == Mode::kVelocity) return velocity_selector_ ? &*velocity_selector_ : nullptr;
  if (mode == Mode::kNavigate) return navigation_selector_ ? &*navigation_selector_ : nullptr;
  return nullptr;
}

const HierarchicalPolicy* Controller::selector(bool navigation) const {
  const std::optional<HierarchicalPolicy>& chosen = navigation ? navigation_selector_ : velocity_selector_;
  return chosen ? &*chosen : nullptr;
}

bool Controller::Submit(const ControlRequest& request) {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  if (queue_count_ == kQueueSize) return false;
  queue_[(queue_head_ + queue_count_) % kQueueSize] = request;
  ++queue_count_;
  return true;
}

void Controller::SubmitUrgent(const ControlRequest& request) {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  if (request.kind == ControlRequest::Kind::kDamp) {
    urgent_damp_ = request;
    have_urgent_damp_ = true;
  } else if (urgent_stop_count_ < kUrgentStops) {
    urgent_stops_[urgent_stop_count_++] = request;
  } else {  // a flood of hand-overs within one tick: stop more than was asked, never less
    ControlRequest& last = urgent_stops_[kUrgentStops - 1];
    last = request;
    last.scope = ControlRequest::Scope::kAny;
  }
}

bool Controller::TakeQueued(ControlRequest& request) {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  if (queue_count_ == 0) return false;
  request = queue_[queue_head_];
  queue_head_ = (queue_head_ + 1) % kQueueSize;
  --queue_count_;
  return true;
}

void Controller::Tick() {
  state_ = backend_.Read();
  ++tick_;

  // Supervise first: a trip overrides whatever a request asks for in this tick.
  const std::string backend_fault = backend_.Fault();  // empty (no allocation) while healthy
  uint32_t faults = backend_fault.empty() ? 0u : kFaultBackend;
  SetText(backend_fault_, backend_fault.c_str());
  hazards_ = Hazards();
  if (MotorsActive()) {
    // A robot rising from the floor, or lying down to rise again, is low until it has stood up.
    const bool rising = mode_ == Mode::kStand && !Braking() && (stand_ticks_ < stand_total_ticks_ || lying_down_);
    faults |= supervisor_.Check(state_, a1::kControlDt, !rising);
  } else {
    supervisor_.Reset();
  }
  if (faults != 0 && mode_ != Mode::kDamp) EnterDamp(faults);

  ControlRequest request;
  while (TakeQueued(request)) Apply(request);
  ControlRequest damp;
  bool have_damp = false;
  int stops = 0;
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    std::swap(have_damp, have_urgent_damp_);
    damp = urgent_damp_;
    std::swap(stops, urgent_stop_count_);
    std::copy_n(urgent_stops_.begin(), stops, taken_stops_.begin());
  }
  for (int i = 0; i < stops; ++i) Apply(taken_stops_[i]);
  if (have_damp) Apply(damp);

  // A skill or velocity task waiting for the stand starts now, so that its policy acts from its
  // first published tick.
  if (mode_ == Mode::kStand && !Braking() && stand_ticks_ >= stand_total_ticks_) SettledStand();
  JointCommand command;
  switch (mode_) {
    case Mode::kStand: command = StandCommand(); break;
    case Mode::kSkill: command = TakeTaskTick() ? SkillCommand() : EndTimedTask(); break;
    case Mode::kVelocity:
    case Mode::kNavigate: command = TakeTaskTick() ? VelocityCommand() : EndTimedTask(); break;
    default: command = DampCommand(); break;
  }
  backend_.Send(command);

  if (task_.state == TaskState::kRunning) {
    task_.elapsed = static_cast<double>(tick_ - task_start_tick_) * a1::kControlDt;
    // While braking, the stand that follows is estimated from where the legs are now.
    const int stand_left = mode_ != Mode::kStand ? 0
                           : Braking() ? brake_ticks_left_ + StandTicks(state_.joint_position, a1::kDefaultJointPos)
                                       : std::max(0, stand_total_ticks_ - stand_ticks_);
    const int task_left = mode_ == Mode::kStand ? pending_ticks_ : task_ticks_left_;
    task_.remaining = (stand_left + task_left) * a1::kControlDt;
  }
  Publish();
}

bool Controller::PolicyActs() const {
  return mode_ == Mode::kSkill || mode_ == Mode::kVelocity || mode_ == Mode::kNavigate;
}

bool Controller::MotorsActive() const {
  return mode_ == Mode::kStand || mode_ == Mode::kSkill || mode_ == Mode::kVelocity ||
         mode_ == Mode::kNavigate;
}

void Controller::Apply(const ControlRequest& request) {
  switch (request.kind) {
    case ControlRequest::Kind::kStand:
      // Never stiffen a robot that is on its side, out of range, or not being sensed (the
      // request side refuses these too; this catches what changed since it looked).
      if (hazards_ != 0) return;
      if (latched_faults_ & kFaultStop) return;  // an emergency stop is lifted on purpose only
      if (task_.state == TaskState::kRunning) EndTask(TaskState::kPreempted, "preempted by stand");
      latched_faults_ = 0;
      fault_message_[0] = '\0';
      recoveries_ = 0;
      if (mode_ != Mode::kStand) EnterStand();
      pending_mode_ = Mode::kIdle;
      break;
    case ControlRequest::Kind::kSkill:
      if (task_.state == TaskState::kRunning) EndTask(TaskState::kPreempted, "preempted by a new skill");
      StartTask(request, dds::CallName(dds::Call::kExecuteSkill));
      if (mode_ == Mode::kDamp) {  // a stop latched after the request side accepted it
        EndTask(TaskState::kSafetyStop, "a safety stop latched before the skill could start");
        return;
      }
      if (hazards_ != 0) {  // as for stand: never stiffen a robot that is down or unsensed
        char why[192];
        DescribeFaults(hazards_, state_, config_.safety, why, sizeof why, backend_fault_.data());
        EndTask(TaskState::kSafetyStop, why);
        return;
      }
      // Every skill starts from the default pose: the state its episodes started from in training.
      recoveries_ = 0;
      EnterStand();
      pending_mode_ = Mode::kSkill;
      pending_skill_ = request.skill;
      pending_ticks_ = std::max(1, Ticks(request.duration));
      break;
    case ControlRequest::Kind::kVelocity: {
      const Mode mode = request.navigate ? Mode::kNavigate : Mode::kVelocity;
      HierarchicalPolicy* hierarchy = Hierarchy(mode);
      if (!hierarchy) return;  // the request side refuses these
      const bool walking = mode_ == Mode::kVelocity || mode_ == Mode::kNavigate;
      if (task_.state == TaskState::kRunning) EndTask(TaskState::kPreempted, "preempted by a new velocity task");
      StartTask(request, dds::CallName(request.navigate ? dds::Call::kNavigate : dds::Call::kTrackVelocity));
      if (mode_ == Mode::kDamp) {
        EndTask(TaskState::kSafetyStop, "a safety stop latched before the task could start");
        return;
      }
      if (hazards_ != 0) {
        char why[192];
        DescribeFaults(hazards_, state_, config_.safety, why, sizeof why, backend_fault_.data());
        EndTask(TaskState::kSafetyStop, why);
        return;
      }
      const std::array<double, 3> command = hierarchy->Clip(request.velocity.data());
      if (walking) {  // already under a selector: change the command without stopping
        // A client may stream one command as a run of tasks: it keeps the held skill and the
        // time-sharing cycle. Another command (or mode) is chosen for at once.
        const Eigen::Vector3d before(velocity_command_.data()), after(command.data());
        if (Hierarchy(mode_) != hierarchy ||
            NearestSkillSelector::Distance(before, after) > TimeSharingSelector::kNewCommand) {
          hierarchy->Reset(skill_);
        }
        velocity_command_ = command;
        mode_ = mode;
        task_ticks_left_ = std::max(1, Ticks(request.duration));
        return;
      }
      velocity_command_ = command;
      recoveries_ = 0;
      EnterStand();
      pending_mode_ = mode;
      pending_ticks_ = std::max(1, Ticks(request.duration));
      break;
    }
    case ControlRequest::Kind::kVelocityUpdate: {
      // While the robot stands up for the task, the task's mode is the pending one.
      const HierarchicalPolicy* hierarchy = Hierarchy(mode_ == Mode::kStand ? pending_mode_ : mode_);
      if (!hierarchy || task_.state != TaskState::kRunning || task_.request_id != request.request_id ||
          task_.client_id != request.client_id) {
        return;  // that task has ended
      }
      velocity_command_ = hierarchy->Clip(request.velocity.data());
      task_.message = request.reason;
      break;
    }
    case ControlRequest::Kind::kStop:
      if (!StopApplies(request)) return;
      if (task_.state == TaskState::kRunning) EndTask(request.stop_state, request.reason.data());
      pending_mode_ = Mode::kIdle;
      if (mode_ != Mode::kDamp && mode_ != Mode::kIdle && mode_ != Mode::kStand) EnterStand();
      break;
    case ControlRequest::Kind::kDamp:
      if (task_.state == TaskState::kRunning) EndTask(TaskState::kCancelled, request.reason.data());
      EnterDamp(kFaultStop);
      stop_client_ = request.client_id;  // the newest press is the one to clear
      stop_time_ = static_cast<double>(tick_) * a1::kControlDt;
      break;
    case ControlRequest::Kind::kClearStop:
      if (!(latched_faults_ & kFaultStop) || request.pressed_at != stop_time_) return;
      latched_faults_ &= ~kFaultStop;
      stop_client_[0] = '\0';
      if (latched_faults_ == 0) {  // nothing else latched: damped and idle until told to stand
        fault_message_[0] = '\0';
        if (mode_ == Mode::kDamp) mode_ = Mode::kIdle;
      } else {
        DescribeFaults(latched_faults_, state_, config_.safety, fault_message_.data(), fault_message_.size(),
                       backend_fault_.data());
      }
      break;
    case ControlRequest::Kind::kReset:
      if (!backend_.CanReset() || (latched_faults_ & kFaultStop)) return;  // as for stand
      if (task_.state == TaskState::kRunning) EndTask(TaskState::kCancelled, "the simulation was reset");
      backend_.Reset();
      state_ = backend_.Read();
      SetText(backend_fault_, backend_.Fault().c_str());
      hazards_ = Hazards();  // of the reset robot: a request after this tick's status may start it
      mode_ = Mode::kIdle;  // the reset robot is at rest: nothing to brake
      latched_faults_ = 0;
      fault_message_[0] = '\0';
      pending_mode_ = Mode::kIdle;
      recoveries_ = 0;
      EnterStand();
      break;
  }
}

bool Controller::StopApplies(const ControlRequest& stop) const {
  const bool running = task_.state == TaskState::kRunning;
  switch (stop.scope) {
    case ControlRequest::Scope::kAny: return true;
    case ControlRequest::Scope::kClient:
      return running && task_.client_id == stop.client_id && (stop.request_id == 0 || task_.request_id < stop.request_id);
    case ControlRequest::Scope::kTask:
      return running && task_.client_id == stop.client_id && task_.request_id == stop.request_id;
  }
  return false;
}

void Controller::EnterStand() {
  lying_down_ = false;
  if (Braking()) return;  // the stand follows the brake
  const int brake = PolicyActs() ? BrakeSkill(skill_) : -1;
  mode_ = Mode::kStand;
  brake_ticks_left_ = Ticks(config_.stand_brake_time);
  skill_ = brake_ticks_left_ > 0 ? brake : -1;
  if (Braking()) return;
  MoveTargets(a1::kDefaultJointPos);
}

int Controller::BrakeSkill(int from) const {
  if (!still_skills_) return -1;
  const double zero[3] = {0.0, 0.0, 0.0};
  const size_t i = still_skills_->NearestCandidate(zero, from);
  const int brake = still_skills_->candidates()[i];
  // NearestCandidate falls back to a recorded fall when every candidate is one: no brake then.
  if (library_.SwitchFell(from, brake)) return -1;
  if (NearestSkillSelector::Distance(still_skills_->velocities()[i], Eigen::Vector3d::Zero()) > kStillSpeed) return -1;
  return brake;
}

uint32_t Controller::Hazards() const {
  return (backend_fault_[0] == '\0' ? 0u : kFaultBackend) | SafetySupervisor::Hazards(state_, config_.safety);
}

void Controller::LieDown() {
  lying_down_ = true;
  MoveTargets(kLyingPose);
}

void Controller::MoveTargets(const a1::JointArray<double>& to) {
  stand_from_ = state_.joint_position;
  stand_to_ = to;
  stand_ticks_ = 0;
  unverified_ticks_ = 0;
  stand_total_ticks_ = StandTicks(stand_from_, to);
  stand_move_ticks_ = stand_total_ticks_ - Ticks(kStandSettle);
}

int Controller::StandTicks(const a1::JointArray<double>& from, const a1::JointArray<double>& to) const {
  double farthest = 0.0;
  for (int j = 0; j < a1::kNumJoints; ++j) farthest = std::max(farthest, std::abs(to[j] - from[j]));
  return std::max(1, Ticks(farthest / config_.stand_joint_speed)) + Ticks(kStandSettle);
}

void Controller::SettledStand() {
  if (lying_down_) {  // down on its belly: now up again
    EnterStand();
    return;
  }
  if (Standing()) {
    unverified_ticks_ = 0;
    if (pending_mode_ != Mode::kIdle) StartPending();
    return;
  }
  if (++unverified_ticks_ < Ticks(config_.stand_check.timeout)) return;  // still settling, maybe
  if (recoveries_ < config_.stand_check.max_recoveries) {
    ++recoveries_;
    LieDown();
    return;
  }
  unverified_ticks_ = 0;
  if (pending_mode_ == Mode::kIdle) return;  // a plain stand holds on as it is
  char why[112];
  Standing(why, sizeof why);
  char message[192];
  std::snprintf(message, sizeof message, "not standing after %d lie-down and stand-up recoveries (%s); not started",
                recoveries_, why);
  EndTask(TaskState::kSafetyStop, message);
  pending_mode_ = Mode::kIdle;
  pending_ticks_ = 0;
}

void Controller::StartPending() {
  mode_ = pending_mode_;
  skill_ = mode_ == Mode::kSkill ? pending_skill_ : -1;
  task_ticks_left_ = pending_ticks_;
  pending_mode_ = Mode::kIdle;
  pending_ticks_ = 0;
  previous_action_.fill(0.0f);  // as at the start of a training episode
  target_filter_.Reset(state_.joint_position);
  if (HierarchicalPolicy* hierarchy = Hierarchy(mode_)) hierarchy->Reset();
}

bool Controller::Standing(char* why, std::size_t size) const {
  const StandCheckConfig& c = config_.stand_check;
  int worst_error = 0, fastest = 0;
  for (int j = 1; j < a1::kNumJoints; ++j) {
    const auto error = [&](int k) { return std::abs(state_.joint_position[k] - a1::kDefaultJointPos[k]); };
    if (!(error(j) <= error(worst_error))) worst_error = j;  // a NaN is the worst
    if (!(std::abs(state_.joint_velocity[j]) <= std::abs(state_.joint_velocity[fastest]))) fastest = j;
  }
  const double tilt = TiltOf(state_);
  const double height = state_.base_position.z();
  const double error = std::abs(state_.joint_position[worst_error] - a1::kDefaultJointPos[worst_error]);
  const double speed = std::abs(state_.joint_velocity[fastest]);
  const double turn_rate = state_.base_angular_velocity.norm();
  const bool upright = tilt <= c.max_tilt;
  const bool high = c.min_base_height <= 0.0 || height >= c.min_base_height;
  const bool posed = error <= c.max_joint_error;
  const bool still = speed <= c.max_joint_speed && turn_rate <= c.max_turn_rate;
  if (upright && high && posed && still) return true;
  if (why == nullptr || size == 0) return false;
  why[0] = '\0';
  std::size_t used = 0;
  const auto add = [&](const char* format, auto... args) {
    const int n = std::snprintf(why + used, size - used, format, used == 0 ? "" : "; ", args...);
    if (n > 0) used = std::min(size - 1, used + static_cast<std::size_t>(n));
  };
  if (!upright) add("%stilt %.2f rad > %.2f", tilt, c.max_tilt);
  if (!high) add("%sbase %.3f m < %.3f", height, c.min_base_height);
  if (!posed) add("%s%s %.2f rad off the stand > %.2f", a1::kJointNames[worst_error], error, c.max_joint_error);
  if (!(speed <= c.max_joint_speed)) add("%s%s at %.1f rad/s > %.1f", a1::kJointNames[fastest], speed, c.max_joint_speed);
  if (!(turn_rate <= c.max_turn_rate)) add("%sbase turning at %.2f rad/s > %.2f", turn_rate, c.max_turn_rate);
  return false;
}

void Controller::EnterDamp(uint32_t faults) {
  if (task_.state == TaskState::kRunning) {
    char message[192];
    DescribeFaults(faults, state_, config_.safety, message, sizeof message, backend_fault_.data());
    EndTask(TaskState::kSafetyStop, message);
  }
  mode_ = Mode::kDamp;
  skill_ = -1;
  pending_mode_ = Mode::kIdle;
  latched_faults_ |= faults;
  ++safety_trips_;
  DescribeFaults(latched_faults_, state_, config_.safety, fault_message_.data(), fault_message_.size(),
                 backend_fault_.data());
}

void Controller::StartTask(const ControlRequest& request, const char* call) {
  task_ = TaskStatus{};
  task_.client_id = request.client_id;
  task_.request_id = request.request_id;
  SetText(task_.call, call);
  task_.state = TaskState::kRunning;
  task_start_tick_ = tick_;
}

void Controller::EndTask(TaskState state, const char* message) {
  task_.state = state;
  task_.remaining = 0.0;
  SetText(task_.message, message);
}

JointCommand Controller::StandCommand() {
  if (Braking()) {
    if (brake_ticks_left_ > 0) {
      --brake_ticks_left_;
      return SkillCommand();
    }
    skill_ = -1;  // braked: now the stand's targets hold the legs
    MoveTargets(a1::kDefaultJointPos);
  }
  const double s = std::min(1.0, static_cast<double>(stand_ticks_) / stand_move_ticks_);
  a1::JointArray<double> target;
  for (int j = 0; j < a1::kNumJoints; ++j) target[j] = stand_from_[j] + s * (stand_to_[j] - stand_from_[j]);
  if (stand_ticks_ < stand_total_ticks_) ++stand_ticks_;
  JointCommand command;
  command.position = target;
  command.kp.fill(config_.stand_kp);
  command.kd.fill(config_.stand_kd);
  return command;
}

JointCommand Controller::SkillCommand() {
  BuildMotionObservation(state_, motion_obs_.data());
  runner_.Act(motion_obs_.data(), previous_action_.data(), skill_, action_.data());
  return PolicyCommand();
}

JointCommand Controller::VelocityCommand() {
  BuildMotionObservation(state_, motion_obs_.data());
  skill_ = Hierarchy(mode_)->Act(motion_obs_.data(), velocity_command_.data(), previous_action_.data(), action_.data());
  return PolicyCommand();
}

JointCommand Controller::PolicyCommand() {
  for (float a : action_) {
    if (!std::isfinite(a)) {
      EnterDamp(kFaultPolicy);
      return DampCommand();
    }
  }
  previous_action_ = action_;
  // The filter sees the targets as training's did; only its output is clamped for the motors.
  a1::JointArray<double> target = target_filter_.Apply(JointTargetsFromAction(action_.data()));
  SafetySupervisor::ClampTargets(target);
  return JointCommand::Track(target);
}

bool Controller::TakeTaskTick() {
  if (task_ticks_left_ <= 0) return false;
  --task_ticks_left_;
  return true;
}

JointCommand Controller::EndTimedTask() {
  if (mode_ == Mode::kNavigate) {
    EndTask(TaskState::kTimeout, "the navigation ran out of time");
  } else {
    EndTask(TaskState::kSucceeded,
            mode_ == Mode::kSkill ? "skill ran for its duration" : "velocity tracked for its duration");
  }
  EnterStand();
  return StandCommand();
}

void Controller::Publish() {
  {
    std::lock_guard<std::mutex> lock(status_mutex_);
    ControllerStatus& s = published_;
    s.state = state_;
    s.tick = tick_;
    s.time = static_cast<double>(tick_) * a1::kControlDt;
    s.mode = mode_;
    s.skill = skill_;
    s.faults = latched_faults_;
    s.fault_message = fault_message_;
    s.safety_trips = safety_trips_;
    s.stop_client = stop_client_;
    s.stop_time = stop_time_;
    s.hazards = hazards_;
    s.backend_fault = backend_fault_;
    s.task = task_;
  }
  status_changed_.notify_all();
}

ControllerStatus Controller::status() const {
  std::lock_guard<std::mutex> lock(status_mutex_);
  return published_;
}

bool Controller::WaitForTickAfter(uint64_t tick, std::chrono::nanoseconds timeout, ControllerStatus& out) const {
  std::unique_lock<std::mutex> lock(status_mutex_);
  if (!status_changed_.wait_for(lock, timeout, [&] { return published_.tick > tick; })) return false;
  out = published_;
  return true;
}

}  // namespace flsd
