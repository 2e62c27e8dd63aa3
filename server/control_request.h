#pragma once
// What the request side asks of the controller, and the fixed-size texts both keep (the control
// tick allocates nothing).

#include <array>
#include <cstddef>
#include <cstdint>

#include "api/modes.h"

namespace flsd {

using FixedText = std::array<char, 192>;
using ClientId = std::array<char, 64>;  // client ids are shorter than this (checked on arrival)

// Copies `text` into `out`, truncating; always terminated.
template <std::size_t N>
void SetText(std::array<char, N>& out, const char* text);

// What the request side asks of the controller.
struct ControlRequest {
  // kVelocity starts a velocity task (track_velocity, or navigate with `navigate` set);
  // kVelocityUpdate changes the command of the running velocity task `request_id` (the navigator's
  // steering), and is ignored once that task has ended. kDamp latches an emergency stop that only
  // kClearStop lifts (stand does not); the robot then stays damped until it is told to stand.
  // kHolder: the control lease has passed to client_id (empty: to nobody); the status names it from
  // the tick that applies it, so that the ok reply to a hand-over follows a state sample showing it.
  enum class Kind { kStand, kSkill, kVelocity, kVelocityUpdate, kStop, kDamp, kClearStop, kReset, kHolder };
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
  FixedText reason{};  // kStop, kDamp: why, for the task's message; kVelocityUpdate: progress
  uint64_t ticket = 0;  // set by RequestQueue: what the controller records a refusal under
};

template <std::size_t N>
void SetText(std::array<char, N>& out, const char* text) {
  std::size_t i = 0;
  for (; text != nullptr && text[i] != '\0' && i + 1 < N; ++i) out[i] = text[i];
  out[i] = '\0';
}

}  // namespace flsd
