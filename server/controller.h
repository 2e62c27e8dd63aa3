#pragma once
// The control tick: the controller's states (below), the policies (a skill, or the selector over
// the skills for a velocity command), the stand sequence and the safety supervisor, in front of a
// Backend. Tick() runs on the control thread and allocates nothing; requests come from the request
// thread through Submit(), and status() is a consistent copy for any thread.

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>

#include "api/modes.h"
#include "robot/backend.h"
#include "robot/observation.h"
#include "robot/target_filter.h"
#include "api/calls.h"
#include "server/control_request.h"
#include "server/request_queue.h"
#include "server/safety.h"
#include "server/server_config.h"
#include "server/stand_sequence.h"
#include "server/task_tracker.h"
#include "skills/runtime/hierarchical_policy.h"
#include "skills/runtime/nearest_skill.h"

namespace flsd {

// The controller's states. Each publishes a Mode; the stand's sub-states publish kStand.
//
//   kIdle      motors slack (at start, after a cleared stop)         -> kRise on stand, skill, velocity
//   kDamp      a latched fault or emergency stop damps the joints      -> kIdle on clear_stop (nothing else latched)
//   kBrake     after a policy, the stillest skill runs on              -> kRise after stand_brake_time
//   kRise      targets move to the stand, then hold while it settles   -> kStand when settled
//   kStand     settled: checked against stand_check every tick         -> the waiting task once standing;
//                                                                        kLieDown to recover; stays otherwise
//   kLieDown   a recovery: targets to the lying pose, held             -> kRise when settled
//   kSkill, kVelocity, kNavigate   a task's policy commands the motors -> kBrake or kRise when it ends
//
// Any state but kIdle goes to kDamp on a fault, a non-finite action or an emergency stop.
enum class ControlState { kIdle, kDamp, kBrake, kRise, kStand, kLieDown, kSkill, kVelocity, kNavigate };

struct ControlStateRow {
  ControlState state;
  Mode mode;          // what the state topic says
  bool motors_on;     // the joints are commanded (and supervised)
  bool task_policy;   // a task's policy commands them (a skill, or a selector's skills)
  bool rising;        // the robot may be low: the supervisor's height check waits
};

// In the order of the enum: kControlStates[int(state)] describes `state`.
inline constexpr ControlStateRow kControlStates[] = {
    {ControlState::kIdle, Mode::kIdle, false, false, false},
    {ControlState::kDamp, Mode::kDamp, false, false, false},
    {ControlState::kBrake, Mode::kStand, true, false, false},
    {ControlState::kRise, Mode::kStand, true, false, true},
    {ControlState::kStand, Mode::kStand, true, false, false},
    {ControlState::kLieDown, Mode::kStand, true, false, true},
    {ControlState::kSkill, Mode::kSkill, true, true, false},
    {ControlState::kVelocity, Mode::kVelocity, true, true, false},
    {ControlState::kNavigate, Mode::kNavigate, true, true, false},
};
constexpr const ControlStateRow& Row(ControlState state) { return kControlStates[static_cast<int>(state)]; }

// The presses of the emergency stop latched now: the newest, and the newest from another client.
// Nobody may undo another's press before stop_hold_time has passed since it; a press of one's own
// bars nothing. The two presses are enough: any older press of a third client is older than both.
struct StopPresses {
  ClientId client{}, other_client{};  // other_client empty: every press is client's
  double time = 0.0, other_time = 0.0;  // s, control time

  void Press(const ClientId& by, double at);
  // When `by` may clear the stop (control time, s): at once if every press is its own.
  double ClearableAt(const char* by, double hold_time) const;
};

// Why a tick refused a request that the request side had accepted: what changed in between (the
// robot became unsafe to move, a stop latched, another client pressed the emergency stop).
struct ApplyRefusal {
  uint64_t ticket = 0;
  uint32_t latched = 0;  // the faults latched then, when they refused it (kFaultStop: an emergency stop)
  uint32_t hazards = 0;  // otherwise, the hazards that did
  FixedText reason{};    // those faults or hazards described then
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
  StopPresses stop;           // who pressed the emergency stop latched now (kFaultStop), and when
  uint64_t applied = 0;       // the newest ticket applied (Submit): every request up to it shows here
  uint32_t hazards = 0;       // SafetySupervisor::Hazards, plus kFaultBackend: what forbids standing now
  FixedText backend_fault{};  // the backend's account of its fault, while it has one
  ClientId controller{};      // the control lease's holder (kHolder), empty if none
  TaskStatus task;
};

class Controller {
 public:
  // `backend` and `library` must outlive the controller.
  Controller(Backend& backend, const SkillLibrary& library, const ServerConfig& config);

  // Queues a request for the next tick. Returns its ticket, which status().applied reaches once a
  // tick has applied it, or 0 if the queue is full (a flood).
  uint64_t Submit(const ControlRequest& request) { return requests_.Submit(request); }

  // For the requests that must never wait behind a full queue or be refused: the emergency stop
  // (kDamp), stops (kStop: a lapsed or released lease, the end of a navigation) and the lease's
  // new holder (kHolder). The next tick applies the stops and the damp after the queue, in the
  // order they came, so they override whatever came with them (RequestQueue). Returns the
  // ticket, as Submit.
  uint64_t SubmitUrgent(const ControlRequest& request) { return requests_.SubmitUrgent(request); }

  // One control period: read the state, supervise, apply queued requests, command the backend.
  void Tick();

  ControllerStatus status() const;
  // What became of the request with `ticket` once status().applied has reached it: applied, or
  // refused by its tick (`refusal` says why), or unknown if so many later refusals have come
  // since that its record is gone.
  enum class Outcome { kApplied, kRefused, kUnknown };
  Outcome OutcomeOf(uint64_t ticket, ApplyRefusal* refusal = nullptr) const;
  // Waits until a tick after `tick` has been published (or `timeout`); copies it to `out`.
  bool WaitForTickAfter(uint64_t tick, std::chrono::nanoseconds timeout, ControllerStatus& out) const;

  const SkillLibrary& library() const { return library_; }
  // Whether the library has a dependable skill within kStillSpeed of still to brake a motion with.
  // Without one a motion's end goes to the stand's targets at once, which can throw a walking robot.
  bool has_brake_skill() const;
  static constexpr double kStillSpeed = 0.1;  // m/s (NearestSkillSelector::Distance from zero)
  // The selector of track_velocity, or of navigate, or nullptr when the server has none for it
  // (the call is then unavailable).
  const HierarchicalPolicy* selector(bool navigation = false) const;
  const ServerConfig& config() const { return config_; }
  bool backend_can_reset() const { return backend_.CanReset(); }

 private:
  // A task that waits for the stand: what starts once the robot stands as it should.
  struct PendingTask {
    ControlState state = ControlState::kIdle;  // kIdle: none
    int skill = -1;
    int ticks = 0;
  };

  // Reads the backend's fault and the state's hazards, checks the supervisor, damps on a fault.
  void Supervise();
  void Apply(const ControlRequest& request);
  void ApplyStand(const ControlRequest& request);
  void ApplySkill(const ControlRequest& request);
  void ApplyVelocity(const ControlRequest& request);
  void ApplyVelocityUpdate(const ControlRequest& request);
  void ApplyStop(const ControlRequest& request);
  void ApplyDamp(const ControlRequest& request);
  void ApplyClearStop(const ControlRequest& request);
  void ApplyReset(const ControlRequest& request);
  // Records that this tick refused `request` (ApplyRefusal), for the reply that waits for it.
  void Refuse(const ControlRequest& request, uint32_t latched, uint32_t hazards);
  // Starts `request`'s task (ending, as preempted by `what`, any that runs). False when the robot
  // may not move now (a stop latched after the request side accepted it, or a hazard): the task
  // has then ended with the reason.
  bool StartMotionTask(const ControlRequest& request, Call call, const char* what);
  // To the stand: first the brake after a policy, then the stand's targets.
  void EnterStand();
  // The dependable skill nearest standing still that the library records no fall for on a switch
  // from `from`; -1 if none is within kStillSpeed of still.
  int BrakeSkill(int from) const;
  // What keeps a motion from starting now: the backend's fault and the state's hazards.
  uint32_t Hazards() const;
  // Once the stand has settled (or a recovery has lain down): starts what waits for it if the
  // robot stands as it should, otherwise recovers or ends the waiting task with the reason.
  void SettledStand();
  void StartPending();
  void EnterDamp(uint32_t faults);
  // This tick's command, by state.
  JointCommand Command();
  JointCommand StandCommand();
  JointCommand SkillCommand();  // skill_'s policy: a skill task's, or the brake's
  JointCommand VelocityCommand();
  // The selector that `state` runs under (kVelocity, kNavigate), or nullptr.
  HierarchicalPolicy* Hierarchy(ControlState state);
  // Checks and applies a policy's joint action.
  JointCommand PolicyCommand();
  // Counts a timed task's tick down; false once its time is up.
  bool TakeTaskTick();
  // A skill or velocity task whose time is up: it succeeded (a navigation timed out); stand.
  JointCommand EndTimedTask();
  JointCommand DampCommand() const { return JointCommand::Damp(config_.safety.damping_kd); }
  // Ticks until the running task ends: the stand it waits for and its own.
  int TaskTicksLeft() const;
  Mode mode() const { return Row(state_).mode; }
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
  RequestQueue requests_;
  StandSequence stand_;
  TaskTracker task_;

  // Control-thread state.
  ControlState state_ = ControlState::kIdle;
  RobotState robot_;
  uint64_t tick_ = 0;
  uint64_t applied_ = 0;  // the newest request ticket applied
  uint32_t latched_faults_ = 0;
  uint32_t hazards_ = 0;
  FixedText fault_message_{};
  FixedText backend_fault_{};  // the backend's account of its fault, while it has one
  uint64_t safety_trips_ = 0;
  StopPresses stop_;
  ClientId holder_{};
  PendingTask pending_;
  int skill_ = -1;  // the skill running (chosen by the selector in the velocity modes; the brake's)
  int task_ticks_left_ = 0;
  std::array<double, 3> velocity_command_{};
  std::array<float, kMotionObsSize> motion_obs_{};
  std::array<float, kActionSize> action_{}, previous_action_{};

  // Shared with other threads.
  mutable std::mutex status_mutex_;
  mutable std::condition_variable status_changed_;
  ControllerStatus published_;
  // Refusals by ticket modulo their count (they come in ticket order). A reply looks its ticket up
  // when the state publisher next wakes, a tick or two later as a rule; 2048 tickets are 128 ticks
  // (2.6 s) of a full queue refused every tick (fewer if urgent calls, which take tickets too, flood
  // beside it), so a refusal outlives any but a long stall of the publisher (the reply then says
  // the outcome is lost).
  static constexpr int kRefusals = 2048;
  std::array<ApplyRefusal, kRefusals> refusals_{};
};

}  // namespace flsd
