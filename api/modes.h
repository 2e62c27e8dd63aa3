#pragma once
// What the robot is doing, how its task stands and how a call was answered, as the project's own
// types: the server keeps them, a client reads them, and no DDS type is needed for either. They
// keep the IDL's values, value for value, so the DDS edge (comm/protocol.h) converts with a cast;
// the tables below name each value once, for people and as the IDL's enumerators end (checked
// against idl/flsd_msgs.idl by tests/api/names_test.cc).

#include <cstddef>

namespace flsd {

enum class Mode { kIdle, kStand, kSkill, kVelocity, kNavigate, kDamp };

// kNone: no task (or, to a client, the state topic has not reported it yet).
enum class TaskState { kNone, kRunning, kSucceeded, kCancelled, kSafetyStop, kPreempted, kLeaseLost, kNoPath, kTimeout };

enum class ReplyStatus {
  kOk,
  kInvalidArgument,
  kUnknownCall,
  kNotInControl,
  kNotAvailable,
  kSafetyStop,
  kDuplicate,
  kDeadlineExceeded,
  kInternal,
  kNoReply,  // never the server's: a client's call that had no reply within its timeout
};

// One value's names: `name` for people (replies, logs, skillctl, the web view), `identifier` as the
// IDL's enumerator ends (MODE_IDLE, STATUS_NOT_IN_CONTROL) and as the Python module spells it.
template <class Enum>
struct EnumName {
  Enum value;
  const char* name;
  const char* identifier;
};

// In the order of each enum: kModeNames[int(mode)] names `mode`.
inline constexpr EnumName<Mode> kModeNames[] = {
    {Mode::kIdle, "idle", "IDLE"},          {Mode::kStand, "stand", "STAND"},
    {Mode::kSkill, "skill", "SKILL"},       {Mode::kVelocity, "velocity", "VELOCITY"},
    {Mode::kNavigate, "navigate", "NAVIGATE"}, {Mode::kDamp, "damp", "DAMP"},
};
inline constexpr EnumName<TaskState> kTaskStateNames[] = {
    {TaskState::kNone, "none", "NONE"},
    {TaskState::kRunning, "running", "RUNNING"},
    {TaskState::kSucceeded, "succeeded", "SUCCEEDED"},
    {TaskState::kCancelled, "cancelled", "CANCELLED"},
    {TaskState::kSafetyStop, "safety stop", "SAFETY_STOP"},
    {TaskState::kPreempted, "preempted", "PREEMPTED"},
    {TaskState::kLeaseLost, "lease lost", "LEASE_LOST"},
    {TaskState::kNoPath, "no path", "NO_PATH"},
    {TaskState::kTimeout, "timeout", "TIMEOUT"},
};
inline constexpr EnumName<ReplyStatus> kReplyStatusNames[] = {
    {ReplyStatus::kOk, "ok", "OK"},
    {ReplyStatus::kInvalidArgument, "invalid argument", "INVALID_ARGUMENT"},
    {ReplyStatus::kUnknownCall, "unknown call", "UNKNOWN_CALL"},
    {ReplyStatus::kNotInControl, "not in control", "NOT_IN_CONTROL"},
    {ReplyStatus::kNotAvailable, "not available", "NOT_AVAILABLE"},
    {ReplyStatus::kSafetyStop, "safety stop", "SAFETY_STOP"},
    {ReplyStatus::kDuplicate, "duplicate", "DUPLICATE"},
    {ReplyStatus::kDeadlineExceeded, "deadline exceeded", "DEADLINE_EXCEEDED"},
    {ReplyStatus::kInternal, "internal error", "INTERNAL"},
    {ReplyStatus::kNoReply, "no reply", "NO_REPLY"},  // the client's alone: not in the IDL
};

// A value's name for people; "unknown" for a value outside its enum (a newer peer's).
const char* Name(Mode mode);
const char* Name(TaskState state);
const char* Name(ReplyStatus status);

}  // namespace flsd
