#pragma once
// What the robot is doing and how its task stands, as the project's own types: the server's
// controller keeps them, a client reads them. They keep the IDL's values, value for value (checked
// in comm/protocol.cc), so the DDS boundary converts with a cast.

namespace flsd {

enum class Mode { kIdle, kStand, kSkill, kVelocity, kNavigate, kDamp };

// kNone: no task (or, to a client, the state topic has not reported it yet).
enum class TaskState { kNone, kRunning, kSucceeded, kCancelled, kSafetyStop, kPreempted, kLeaseLost, kNoPath, kTimeout };

}  // namespace flsd
