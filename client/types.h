#pragma once
// The client's own types: what a script sees of skilld's replies, skills, tasks and state, with
// no IDL struct or C enum in sight. Its enums, and their names (Name), are the server's too
// (api/modes.h), with the IDL's values, so converting is a cast.

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "api/modes.h"

namespace flsd {

struct Reply {
  uint64_t request_id = 0;  // the call's: its task on the state topic carries it
  ReplyStatus status = ReplyStatus::kNoReply;
  std::string message;
  std::string safety_report;  // safety trips since this client's last reply, if any
  bool ok() const { return status == ReplyStatus::kOk; }
  bool answered() const { return status != ReplyStatus::kNoReply; }
  // "ok: ...", "not in control: ...", or "no reply from skilld".
  std::string Describe() const;
};

// A refused call where the API has nothing else to return (ListSkills).
class CallError : public std::runtime_error {
 public:
  explicit CallError(Reply reply) : std::runtime_error(reply.Describe()), reply_(std::move(reply)) {}
  const Reply& reply() const { return reply_; }

 private:
  Reply reply_;
};

// What the library measured of one skill in its evaluation.
struct SkillInfo {
  int id = 0;
  std::array<double, 3> linear_velocity{};   // mean, body frame, m/s
  std::array<double, 3> angular_velocity{};  // mean, body frame, rad/s
  double base_height = 0.0;                  // mean, m
  double gait_frequency = 0.0;               // Hz
  int survival_steps = 0;
};

// The progress, then the result, of a long call (execute_skill, track_velocity, navigate).
struct TaskReport {
  std::string client_id;
  uint64_t request_id = 0;
  std::string call;
  TaskState state = TaskState::kNone;
  double elapsed = 0.0;    // s
  double remaining = 0.0;  // s
  std::string message;
  std::vector<double> path;  // navigate: the planned path now, x0 y0 x1 y1 ... (world frame, m)
  bool ended() const { return state != TaskState::kNone && state != TaskState::kRunning; }
};

// One sample of the state topic.
struct StateReport {
  double time = 0.0;  // s since the server started its loop
  uint64_t tick = 0;
  std::string backend;  // sim, hw
  Mode mode = Mode::kIdle;
  int skill = -1;                          // active skill (in stand: the still skill braking the last motion), -1 if none
  std::array<double, 3> position{};        // base, world frame, m
  std::array<double, 4> orientation{};     // base, w x y z, body to world
  std::array<double, 3> linear_velocity{};   // base, body frame, m/s
  std::array<double, 3> angular_velocity{};  // base, body frame, rad/s
  std::array<double, 12> joint_position{};   // rad, robot/a1.h order
  std::array<double, 12> joint_velocity{};   // rad/s
  std::array<double, 12> joint_torque{};     // N m
  std::array<bool, 4> foot_contact{};        // FR FL RR RL
  uint32_t faults = 0;                       // nonzero while a safety stop is latched
  std::string fault_message;
  std::string controller;  // the client holding the control lease, empty if none
  uint64_t deadline_misses = 0;
  uint64_t requests_dropped = 0;
  TaskReport task;
  double yaw() const;  // rad, from the orientation
};

}  // namespace flsd
