#pragma once
// The control tick: modes (Idle, Stand, Skill k, Velocity, Navigate, Damp), the policies (a skill,
// or the selector over the skills for a velocity command), and the safety supervisor,
// in front of a Backend. Tick() runs on the control thread and allocates nothing; requests come
// from the request thread through Submit(), and status() is a consistent copy for any thread.

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>

#include "comm/modes.h"
#include "robot/backend.h"
#include "robot/observation.h"
#include "robot/target_filter.h"
#include "server/safety.h"
#include "server/server_config.h"
#include "skills/runtime/hierarchical_policy.h"
#include "skills/runtime/nearest_skill.h"

namespace flsd {

using FixedText = std::array<char, 192>;
using ClientId = std::array<char, 64>;  // client ids are shorter than this (checked on arrival)

// Copies `text` into `out`, truncating; always terminated.
template <std::size_t N>
void SetText(std::array<char, N>& out, const char* text);

// Which request a long call is, and how it is going (published as RobotState.task).
struct TaskStatus {
  ClientId client_id{};
  uint64_t request_id = 0;
  std::array<char, 24> call{};
  TaskState state = TaskState::kNone;
  double elapsed = 0.0;    // s since the request was taken
  double remaining = 0.0;  // s until it ends (standing up included)
  FixedText message{};
};

// Everything the server publishes about one tick.
struct ControllerStatus {
  RobotState state;
  uint64_t tick = 0;
  double time = 0.0;  // s, tick * control period
  Mode mode = Mode::kIdle;
  int skill = -1;
  uint32_t faults = 0;  // latched since the last stop; zero while none is latched
  FixedText fault_message{};
  uint64_t safety_trips = 0;  // ever; a client compares counts to learn of new trips
  ClientId stop_client{};     // who pressed the emergency stop latched now (kFaultStop)
  double stop_time = 0.0;     // s, when it was pressed
  uint32_t hazards = 0;       // SafetySupervisor::Hazards, plus kFaultBackend: what forbids standing now
  FixedText backend_fault{};  // the backend's account of its fault, while it has one
  TaskStatus task;
};

// What the request side asks of the controller.
struct ControlRequest {
  // kVelocity starts a velocity task (track_velocity, or navigate with `navigate` set);
  // kVelocityUpdate changes the command of the running velocity task `request_id` (the navigator's
  // steering), and is ignored once that task has ended. kDamp latches an emergency stop that only
  // kClearStop lifts (stand does not); the robot then stays damped until it is told to stand.
  enum class Kind { kStand, kSkill, kVelocity, kVelocityUpdate, kStop, kDamp, kClearStop, kReset };
  Kind kind = Kind::kStand;
  int skill = 0;
  double duration = 0.0;  // s, kSkill and kVelocity
  std::array<double, 3> velocity{};  // kVelocity, kVelocityUpdate: vx, vy (m/s), wz (rad/s), body frame
  bool navigate = false;             // kVelocity: a navigation's task
  ClientId client_id{};
  uint64_t request_id = 0;
  TaskState stop_state = TaskState::kCancelled;  // kStop: how the current task ends
  // kStop: what it ends. A stop on behalf of one client (its lease lapsed, it released control)
  // must not end the task of the client that took control after it.
  // kClient with a request_id: only a task from before it (a release must not end the task the same
  // client starts next, which the queue applies first when both come within one tick).
  enum class Scope { kAny, kClient, kTask };  // whatever runs; client_id's task; request_id's task
  Scope scope = Scope::kAny;
  double pressed_at = 0.0;  // kClearStop: the press it clears (ControllerStatus.stop_time); a later one stays
  FixedText reason{};  // kStop, kDamp: why, for the task's message; kVelocityUpdate: progress
};

class Controller {
 public:
  // `backend` and `library` must outlive the controller.
  Controller(Backend& backend, const SkillLibrary& library, const ServerConfig& config);

  // Queues a request for the next tick. Returns false if the queue is full (a flood).
  bool Submit(const ControlRequest& request);

  // For the requests that must never wait behind a full queue or be refused: the emergency stop
  // (kDamp) and stops (kStop: a lapsed or released lease, the end of a navigation). The next tick
  // applies them after the queue, in the order they came, so they override whatever came with
  // them. The newest damp is kept; stops beyond kUrgentStops merge into one stop of whatever runs.
  void SubmitUrgent(const ControlRequest& request);

  // One control period: read the state, supervise, apply queued requests, command the backend.
  void Tick();

  ControllerStatus status() const;
  // Waits until a tick after `tick` has been published (or `timeout`); copies it to `out`.
  bool WaitForTickAfter(uint64_t tick, std::chrono::nanoseconds timeout, ControllerStatus& out) const;

  const SkillLibrary& library() const { return library_; }
  // The selector of track_velocity, or of navigate, or nullptr when the server has none for it
  // (the call is then unavailable).
  const HierarchicalPolicy* selector(bool navigation = false) const;
  const ServerConfig& config() const { return config_; }
  bool backend_can_reset() const { return backend_.CanReset(); }

 private:
  static constexpr int kQueueSize = 16;
  static constexpr int kUrgentStops = 8;

  void Apply(const ControlRequest& request);
  bool StopApplies(const ControlRequest& stop) const;
  bool TakeQueued(ControlRequest& request);
  // To the default pose. After a policy, the library's stillest skill first runs for
  // stand_brake_time (BrakeSkill): holding the legs where a fast skill left them tips the robot.
  void EnterStand();
  // The dependable skill nearest standing still that the library records no fall for on a switch
  // from `from`; -1 if none is within kStillSpeed of still.
  int BrakeSkill(int from) const;
  static constexpr double kStillSpeed = 0.1;  // m/s (NearestSkillSelector::Distance from zero)
  // Recovery: targets to kLyingPose, then (SettledStand) up again.
  void LieDown();
  // What keeps a motion from starting now: the backend's fault and the state's hazards.
  uint32_t Hazards() const;
  void MoveTargets(const a1::JointArray<double>& to);
  // Joint targets move at stand_joint_speed, then hold for kStandSettle, so that a skill starts
  // from rest: the ticks that takes from `from` to `to`.
  int StandTicks(const a1::JointArray<double>& from, const a1::JointArray<double>& to) const;
  static constexpr double kStandSettle = 0.5;  // s
  // Once a stand has settled: starts what waits for it if the robot stands as it should,
  // otherwise recovers or ends the waiting task with the reason.
  void SettledStand();
  void StartPending();
  // Whether the robot stands within config.stand_check; if not and `why` is given, says how not.
  bool Standing(char* why = nullptr, std::size_t size = 0) const;
  void EnterDamp(uint32_t faults);
  void StartTask(const ControlRequest& request, const char* call);
  void EndTask(TaskState state, const char* message);
  JointCommand StandCommand();
  JointCommand SkillCommand();  // skill_'s policy: a skill task's, or the brake's
  JointCommand VelocityCommand();
  // The selector that mode runs under (kVelocity, kNavigate), or nullptr.
  HierarchicalPolicy* Hierarchy(Mode mode);
  // Checks and applies a policy's joint action.
  JointCommand PolicyCommand();
  // Counts a timed task's tick down; false once its time is up.
  bool TakeTaskTick();
  // A skill or velocity task whose time is up: it succeeded (a navigation timed out); stand.
  JointCommand EndTimedTask();
  JointCommand DampCommand() const { return JointCommand::Damp(config_.safety.damping_kd); }
  bool MotorsActive() const;
  bool PolicyActs() const;  // a skill, velocity or navigation task's policy commands the motors
  bool Braking() const { return mode_ == Mode::kStand && skill_ >= 0; }
  void Publish();

  Backend& backend_;
  const SkillLibrary& library_;
  ServerConfig config_;
  SafetySupervisor supervisor_;
  PolicyRunner runner_;
  // The velocity mode's and the navigation mode's selectors (config selector, navigation.selector).
  std::optional<HierarchicalPolicy> velocity_selector_, navigation_selector_;
  TargetFilter target_filter_;  // the library's, as in training
  std::optional<NearestSkillSelector> still_skills_;  // BrakeSkill's candidates

  // Control-thread state.
  RobotState state_;
  uint64_t tick_ = 0;
  Mode mode_ = Mode::kIdle;
  uint32_t latched_faults_ = 0;
  uint32_t hazards_ = 0;
  FixedText fault_message_{};
  FixedText backend_fault_{};  // the backend's account of its fault, while it has one
  uint64_t safety_trips_ = 0;
  ClientId stop_client_{};
  double stop_time_ = 0.0;
  TaskStatus task_;
  uint64_t task_start_tick_ = 0;
  a1::JointArray<double> stand_from_{}, stand_to_{};
  bool lying_down_ = false;   // a recovery's first half
  int recoveries_ = 0;        // since the last request
  int unverified_ticks_ = 0;  // settled, but not standing as it should
  int stand_ticks_ = 0;
  int stand_move_ticks_ = 1;   // moving the targets to the default pose
  int stand_total_ticks_ = 1;  // then holding them while the robot settles
  int brake_ticks_left_ = 0;   // while Braking(): its policy's ticks before the stand moves the targets
  // What starts once standing: a skill, or a velocity task; kIdle for nothing.
  Mode pending_mode_ = Mode::kIdle;
  int pending_skill_ = -1;
  int pending_ticks_ = 0;
  int skill_ = -1;  // the skill running (chosen by the selector in the velocity modes; the brake in kStand)
  int task_ticks_left_ = 0;
  std::array<double, 3> velocity_command_{};
  std::array<float, kMotionObsSize> motion_obs_{};
  std::array<float, kActionSize> action_{}, previous_action_{};

  // Shared with other threads.
  mutable std::mutex queue_mutex_;
  std::array<ControlRequest, kQueueSize> queue_{};
  int queue_head_ = 0, queue_count_ = 0;
  ControlRequest urgent_damp_;
  bool have_urgent_damp_ = false;
  std::array<ControlRequest, kUrgentStops> urgent_stops_{};
  int urgent_stop_count_ = 0;
  std::array<ControlRequest, kUrgentStops> taken_stops_{};  // control thread: the tick's copy
  mutable std::mutex status_mutex_;
  mutable std::condition_variable status_changed_;
  ControllerStatus published_;
};

template <std::size_t N>
void SetText(std::array<char, N>& out, const char* text) {
  std::size_t i = 0;
  for (; text != nullptr && text[i] != '\0' && i + 1 < N; ++i) out[i] = text[i];
  out[i] = '\0';
}

}  // namespace flsd
