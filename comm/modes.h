#pragma once
// What the robot is doing, how its task stands and how a call was answered, as the project's own
// types: the server keeps them, a client reads them. They keep the IDL's values, value for value (checked
// in comm/protocol.cc), so the DDS boundary converts with a cast.

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

}  // namespace flsd
