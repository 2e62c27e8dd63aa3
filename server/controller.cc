#include "server/controller.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <limits>


namespace flsd {
namespace {

int Ticks(double seconds) { return static_cast<int>(std::lround(seconds / a1::kControlDt)); }

constexpr bool RowsInEnumOrder() {
  for (std::size_t i = 0; i < std::size(kControlStates); ++i) {
    if (static_cast<std::size_t>(kControlStates[i].state) != i) return false;
  }
  return std::size(kControlStates) == static_cast<std::size_t>(ControlState::kNavigate) + 1;
}
static_assert(RowsInEnumOrder(), "kControlStates: one row per state, in the order of the enum");

// The selector `selector` names (ServedSelectorKind), or none.
std::optional<HierarchicalPolicy> MakeHierarchy(const SkillLibrary& library, const char* key,
                                                const std::string& selector, SelectorKind analytic) {
  try {
    const std::optional<SelectorKind> kind = ServedSelectorKind(library, selector, analytic);
    return kind ? std::optional<HierarchicalPolicy>(std::in_place, library, *kind) : std::nullopt;
  } catch (const InputError& e) {
    throw InputError(std::string("server config ") + key + ": " + e.what());
  }
}

}  // namespace

void StopPresses::Press(const ClientId& by, double at) {
  if (std::strcmp(by.data(), client.data()) != 0) {
    other_client = client;  // empty before the first press: nobody else's press then
    other_time = time;
    client = by;
  }
  time = at;
}

double StopPresses::ClearableAt(const char* by, double hold_time) const {
  if (std::strcmp(by, client.data()) != 0) return time + hold_time;
  if (other_client[0] == '\0') return -std::numeric_limits<double>::infinity();
  return other_time + hold_time;
}

Controller::Controller(Backend& backend, const SkillLibrary& library, const ServerConfig& config)
    : backend_(backend),
      library_(library),
      config_(config),
      supervisor_(config.safety),
      runner_(library),
      velocity_selector_(MakeHierarchy(library, "selector", config.selector, SelectorKind::kTimeSharing)),
      navigation_selector_(
          MakeHierarchy(library, "navigation.selector", config.navigation.selector, SelectorKind::kNearestSkill)),
      target_filter_(library.action_filter_hz(), library.action_filter_order()),
      stand_(config_) {
  try {
    still_skills_.emplace(library);
  } catch (const InputError&) {  // no dependable skill: the stand follows a policy at once
  }
  robot_ = backend_.Read();
  Publish();
}

HierarchicalPolicy* Controller::Hierarchy(ControlState state) {
  if (state == ControlState::kVelocity) return velocity_selector_ ? &*velocity_selector_ : nullptr;
  if (state == ControlState::kNavigate) return navigation_selector_ ? &*navigation_selector_ : nullptr;
  return nullptr;
}

const HierarchicalPolicy* Controller::selector(bool navigation) const {
  const std::optional<HierarchicalPolicy>& chosen = navigation ? navigation_selector_ : velocity_selector_;
  return chosen ? &*chosen : nullptr;
}

void Controller::Tick() {
  robot_ = backend_.Read();
  ++tick_;
  Supervise();  // first: a trip overrides whatever a request asks for in this tick
  applied_ = requests_.TakeAll([this](const ControlRequest& request) { Apply(request); });
  // A task waiting for the stand starts now, so that its policy acts from its first published tick.
  if (state_ == ControlState::kStand || (state_ == ControlState::kLieDown && stand_.settled())) SettledStand();
  backend_.Send(Command());
  task_.Update(tick_, TaskTicksLeft(), a1::kControlDt);
  Publish();
}

void Controller::Supervise() {
  const std::string backend_fault = backend_.Fault();  // empty (no allocation) while healthy
  uint32_t faults = backend_fault.empty() ? 0u : kFaultBackend;
  SetText(backend_fault_, backend_fault.c_str());
  hazards_ = Hazards();
  if (Row(state_).motors_on) {
    // A robot rising from the floor, or lying down to rise again, is low until it has stood up.
    faults |= supervisor_.Check(robot_, a1::kControlDt, !Row(state_).rising);
  } else {
    supervisor_.Reset();
  }
  if (faults != 0 && state_ != ControlState::kDamp) EnterDamp(faults);
}

JointCommand Controller::Command() {
  switch (state_) {
    case ControlState::kIdle:
    case ControlState::kDamp: return DampCommand();
    case ControlState::kBrake:
    case ControlState::kRise:
    case ControlState::kStand:
    case ControlState::kLieDown: return StandCommand();
    case ControlState::kSkill: return TakeTaskTick() ? SkillCommand() : EndTimedTask();
    case ControlState::kVelocity:
    case ControlState::kNavigate: return TakeTaskTick() ? VelocityCommand() : EndTimedTask();
  }
  return DampCommand();
}

int Controller::TaskTicksLeft() const {
  if (mode() != Mode::kStand) return task_ticks_left_;
  // While braking, the stand that follows is estimated from where the legs are now.
  const int stand_left = state_ == ControlState::kBrake
                             ? stand_.brake_ticks_left() + stand_.Ticks(robot_.joint_position, a1::kDefaultJointPos)
                             : stand_.ticks_left();
  return stand_left + pending_.ticks;
}

void Controller::Apply(const ControlRequest& request) {
  using Kind = ControlRequest::Kind;
  switch (request.kind) {
    case Kind::kStand: ApplyStand(request); break;
    case Kind::kSkill: ApplySkill(request); break;
    case Kind::kVelocity: ApplyVelocity(request); break;
    case Kind::kVelocityUpdate: ApplyVelocityUpdate(request); break;
    case Kind::kStop: ApplyStop(request); break;
    case Kind::kDamp: ApplyDamp(request); break;
    case Kind::kClearStop: ApplyClearStop(request); break;
    case Kind::kReset: ApplyReset(request); break;
    case Kind::kHolder: holder_ = request.client_id; break;
  }
}

void Controller::ApplyStand(const ControlRequest& request) {
  // An emergency stop is lifted on purpose only, and a robot on its side, out of range or not
  // being sensed is never stiffened. The request side refuses these too; this catches what
  // changed since it looked, in the order it checks.
  if (latched_faults_ & kFaultStop) return Refuse(request, latched_faults_, 0);
  if (hazards_ != 0) return Refuse(request, 0, hazards_);
  task_.End(TaskState::kPreempted, "preempted by stand");
  latched_faults_ = 0;
  fault_message_[0] = '\0';
  stand_.ResetRecoveries();
  if (mode() != Mode::kStand) EnterStand();
  pending_ = PendingTask{};
}

bool Controller::StartMotionTask(const ControlRequest& request, Call call, const char* what) {
  char preempted[64];
  std::snprintf(preempted, sizeof preempted, "preempted by a new %s", what);
  const char* noun = call == Call::kExecuteSkill ? "skill" : "task";
  task_.End(TaskState::kPreempted, preempted);
  task_.Start(request, CallName(call), tick_);
  if (state_ == ControlState::kDamp) {  // a stop latched after the request side accepted it
    char why[96];
    std::snprintf(why, sizeof why, "a safety stop latched before the %s could start", noun);
    task_.End(TaskState::kSafetyStop, why);
    Refuse(request, latched_faults_, 0);
    return false;
  }
  if (hazards_ != 0) {  // as for stand: never stiffen a robot that is down or unsensed
    char why[192];
    DescribeFaults(hazards_, robot_, config_.safety, why, sizeof why, backend_fault_.data());
    task_.End(TaskState::kSafetyStop, why);
    Refuse(request, 0, hazards_);
    return false;
  }
  return true;
}

void Controller::ApplySkill(const ControlRequest& request) {
  if (!StartMotionTask(request, Call::kExecuteSkill, "skill")) return;
  // Every skill starts from the default pose: the state its episodes started from in training.
  stand_.ResetRecoveries();
  EnterStand();
  pending_ = {ControlState::kSkill, request.skill, std::max(1, Ticks(request.duration))};
}

void Controller::ApplyVelocity(const ControlRequest& request) {
  const ControlState next = request.navigate ? ControlState::kNavigate : ControlState::kVelocity;
  HierarchicalPolicy* hierarchy = Hierarchy(next);
  if (!hierarchy) return;  // the request side refuses these
  const bool walking = state_ == ControlState::kVelocity || state_ == ControlState::kNavigate;
  if (!StartMotionTask(request, request.navigate ? Call::kNavigate : Call::kTrackVelocity, "velocity task")) return;
  const std::array<double, 3> command = hierarchy->Clip(request.velocity.data());
  if (walking) {  // already under a selector: change the command without stopping
    // A client may stream one command as a run of tasks: it keeps the held skill and the
    // time-sharing cycle. Another command (or mode) is chosen for at once.
    const Eigen::Vector3d before(velocity_command_.data()), after(command.data());
    if (Hierarchy(state_) != hierarchy ||
        NearestSkillSelector::Distance(before, after) > TimeSharingSelector::kNewCommand) {
      hierarchy->Reset(skill_);
    }
    velocity_command_ = command;
    state_ = next;
    task_ticks_left_ = std::max(1, Ticks(request.duration));
    return;
  }
  velocity_command_ = command;
  stand_.ResetRecoveries();
  EnterStand();
  pending_ = {next, -1, std::max(1, Ticks(request.duration))};
}

void Controller::ApplyVelocityUpdate(const ControlRequest& request) {
  // While the robot stands up for the task, the task's state is the pending one.
  const HierarchicalPolicy* hierarchy = Hierarchy(mode() == Mode::kStand ? pending_.state : state_);
  if (!hierarchy || !task_.IsRunning(request)) return;  // that task has ended
  velocity_command_ = hierarchy->Clip(request.velocity.data());
  task_.SetMessage(request.reason);
}

void Controller::ApplyStop(const ControlRequest& request) {
  if (!task_.StoppedBy(request)) return;
  task_.End(request.stop_state, request.reason.data());
  pending_ = PendingTask{};
  if (Row(state_).task_policy) EnterStand();
}

void Controller::ApplyDamp(const ControlRequest& request) {
  task_.End(TaskState::kCancelled, request.reason.data());
  EnterDamp(kFaultStop);
  stop_.Press(request.client_id, static_cast<double>(tick_) * a1::kControlDt);
}

void Controller::ApplyClearStop(const ControlRequest& request) {
  if (!(latched_faults_ & kFaultStop)) return;  // cleared already: what the caller asked for holds
  // Another client may have pressed it since the request side looked.
  const double now = static_cast<double>(tick_) * a1::kControlDt;
  if (now < stop_.ClearableAt(request.client_id.data(), config_.safety.stop_hold_time)) {
    return Refuse(request, latched_faults_, 0);
  }
  latched_faults_ &= ~kFaultStop;
  stop_ = StopPresses{};
  if (latched_faults_ == 0) {  // nothing else latched: damped and idle until told to stand
    fault_message_[0] = '\0';
    if (state_ == ControlState::kDamp) state_ = ControlState::kIdle;
  } else {
    DescribeFaults(latched_faults_, robot_, config_.safety, fault_message_.data(), fault_message_.size(),
                   backend_fault_.data());
  }
}

void Controller::ApplyReset(const ControlRequest& request) {
  if (!backend_.CanReset()) return;  // the request side refuses it: the backend never changes
  if (latched_faults_ & kFaultStop) return Refuse(request, latched_faults_, 0);  // as for stand
  task_.End(TaskState::kCancelled, "the simulation was reset");
  backend_.Reset();
  robot_ = backend_.Read();
  SetText(backend_fault_, backend_.Fault().c_str());
  hazards_ = Hazards();  // of the reset robot: a request after this tick's status may start it
  state_ = ControlState::kIdle;  // the reset robot is at rest: nothing to brake
  latched_faults_ = 0;
  fault_message_[0] = '\0';
  pending_ = PendingTask{};
  stand_.ResetRecoveries();
  EnterStand();
}

void Controller::Refuse(const ControlRequest& request, uint32_t latched, uint32_t hazards) {
  if (request.ticket == 0) return;  // not from the queue: nobody waits for it
  ApplyRefusal refusal;
  refusal.ticket = request.ticket;
  refusal.latched = latched;
  refusal.hazards = hazards;
  if (latched != 0) {
    refusal.reason = fault_message_;
  } else {
    DescribeFaults(hazards, robot_, config_.safety, refusal.reason.data(), refusal.reason.size(),
                   backend_fault_.data());
  }
  std::lock_guard<std::mutex> lock(status_mutex_);  // rare: only a refusal takes it mid-tick
  refusals_[request.ticket % kRefusals] = refusal;
}

Controller::Outcome Controller::OutcomeOf(uint64_t ticket, ApplyRefusal* refusal) const {
  std::lock_guard<std::mutex> lock(status_mutex_);
  const ApplyRefusal& slot = refusals_[ticket % kRefusals];
  if (slot.ticket > ticket) return Outcome::kUnknown;  // a later refusal took its slot
  if (slot.ticket < ticket) return Outcome::kApplied;  // its refusal would have taken the slot
  if (refusal != nullptr) *refusal = slot;
  return Outcome::kRefused;
}

void Controller::EnterStand() {
  if (state_ == ControlState::kBrake) return;  // the stand follows the brake
  const int brake = Row(state_).task_policy ? BrakeSkill(skill_) : -1;
  stand_.StartBrake();
  if (brake >= 0 && stand_.brake_ticks_left() > 0) {
    state_ = ControlState::kBrake;
    skill_ = brake;
    return;
  }
  state_ = ControlState::kRise;
  skill_ = -1;
  stand_.MoveTo(robot_, a1::kDefaultJointPos);
}

bool Controller::has_brake_skill() const {
  if (!still_skills_) return false;
  for (const Eigen::Vector3d& velocity : still_skills_->velocities()) {
    if (NearestSkillSelector::Distance(velocity, Eigen::Vector3d::Zero()) <= kStillSpeed) return true;
  }
  return false;
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
  return (backend_fault_[0] == '\0' ? 0u : kFaultBackend) | SafetySupervisor::Hazards(robot_, config_.safety);
}

void Controller::SettledStand() {
  if (state_ == ControlState::kLieDown) {  // down on its belly: now up again
    EnterStand();
    return;
  }
  switch (stand_.Verify(robot_)) {
    case StandSequence::Verdict::kStanding:
      if (pending_.state != ControlState::kIdle) StartPending();
      return;
    case StandSequence::Verdict::kSettling: return;  // still settling, maybe
    case StandSequence::Verdict::kRecover:
      state_ = ControlState::kLieDown;
      stand_.MoveTo(robot_, StandSequence::kLyingPose);
      return;
    case StandSequence::Verdict::kFailed: break;
  }
  if (pending_.state == ControlState::kIdle) return;  // a plain stand holds on as it is
  char why[112];
  stand_.Standing(robot_, why, sizeof why);
  char message[192];
  std::snprintf(message, sizeof message, "not standing after %d lie-down and stand-up recoveries (%s); not started",
                stand_.recoveries(), why);
  task_.End(TaskState::kSafetyStop, message);
  pending_ = PendingTask{};
}

void Controller::StartPending() {
  state_ = pending_.state;
  skill_ = state_ == ControlState::kSkill ? pending_.skill : -1;
  task_ticks_left_ = pending_.ticks;
  pending_ = PendingTask{};
  previous_action_.fill(0.0f);  // as at the start of a training episode
  target_filter_.Reset(robot_.joint_position);
  if (HierarchicalPolicy* hierarchy = Hierarchy(state_)) hierarchy->Reset();
}

void Controller::EnterDamp(uint32_t faults) {
  if (task_.running()) {
    char message[192];
    DescribeFaults(faults, robot_, config_.safety, message, sizeof message, backend_fault_.data());
    task_.End(TaskState::kSafetyStop, message);
  }
  state_ = ControlState::kDamp;
  skill_ = -1;
  pending_ = PendingTask{};
  latched_faults_ |= faults;
  ++safety_trips_;
  DescribeFaults(latched_faults_, robot_, config_.safety, fault_message_.data(), fault_message_.size(),
                 backend_fault_.data());
}

JointCommand Controller::StandCommand() {
  if (state_ == ControlState::kBrake) {
    if (stand_.TakeBrakeTick()) return SkillCommand();
    state_ = ControlState::kRise;  // braked: now the stand's targets hold the legs
    skill_ = -1;
    stand_.MoveTo(robot_, a1::kDefaultJointPos);
  }
  const JointCommand command = stand_.Command();
  if (state_ == ControlState::kRise && stand_.settled()) state_ = ControlState::kStand;
  return command;
}

JointCommand Controller::SkillCommand() {
  BuildMotionObservation(robot_, motion_obs_.data());
  runner_.Act(motion_obs_.data(), previous_action_.data(), skill_, action_.data());
  return PolicyCommand();
}

JointCommand Controller::VelocityCommand() {
  BuildMotionObservation(robot_, motion_obs_.data());
  skill_ = Hierarchy(state_)->Act(motion_obs_.data(), velocity_command_.data(), previous_action_.data(), action_.data());
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
  if (state_ == ControlState::kNavigate) {
    task_.End(TaskState::kTimeout, "the navigation ran out of time");
  } else {
    task_.End(TaskState::kSucceeded,
              state_ == ControlState::kSkill ? "skill ran for its duration" : "velocity tracked for its duration");
  }
  EnterStand();
  return StandCommand();
}

void Controller::Publish() {
  {
    std::lock_guard<std::mutex> lock(status_mutex_);
    ControllerStatus& s = published_;
    s.state = robot_;
    s.tick = tick_;
    s.time = static_cast<double>(tick_) * a1::kControlDt;
    s.mode = mode();
    s.skill = skill_;
    s.faults = latched_faults_;
    s.fault_message = fault_message_;
    s.safety_trips = safety_trips_;
    s.stop = stop_;
    s.applied = applied_;
    s.hazards = hazards_;
    s.backend_fault = backend_fault_;
    s.controller = holder_;
    s.task = task_.status();
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
