#pragma once
// What server and client must agree on beyond the IDL types: topic names, QoS, the calls, and
// the names of the enums for people. The tables here are the only place these names are spelled.

#include <optional>
#include <string>
#include <string_view>

#include "comm/dds.h"
#include "comm/modes.h"
#include "flsd_msgs.h"

namespace flsd::dds {

inline constexpr const char* kRequestTopic = "flsd/request";
inline constexpr const char* kReplyTopic = "flsd/reply";
inline constexpr const char* kStateTopic = "flsd/state";

// Requests and replies are reliable with room for bursts; state is best effort, newest only:
// a late telemetry sample is worth nothing, and must never hold up the next one.
inline constexpr EndpointQos kRequestQos = EndpointQos::Reliable(64);
inline constexpr EndpointQos kReplyQos = EndpointQos::Reliable(64);
inline constexpr EndpointQos kStateQos = EndpointQos::BestEffort(1);

// The calls of Request.call. The IDL carries a name, so that an unknown call stays answerable.
enum class Call {
  kListSkills,
  kStatus,
  kExecuteSkill,
  kTrackVelocity,
  kNavigate,
  kStop,
  kStand,
  kDamp,
  kClearStop,
  kAcquireControl,
  kRenewControl,
  kReleaseControl,
  kReset,
};

struct CallSpec {
  Call call;
  const char* name;
  bool needs_control;  // refused unless the caller holds the control lease
  bool long_running;   // accepted at once; progress and result on the state topic
};

// In the order of the enum: kCallSpecs[int(call)] describes `call`.
inline constexpr CallSpec kCallSpecs[] = {
    {Call::kListSkills, "list_skills", false, false},
    {Call::kStatus, "status", false, false},
    {Call::kExecuteSkill, "execute_skill", true, true},
    {Call::kTrackVelocity, "track_velocity", true, true},
    {Call::kNavigate, "navigate", true, true},
    {Call::kStop, "stop", true, false},
    {Call::kStand, "stand", true, false},
    {Call::kDamp, "damp", false, false},
    {Call::kClearStop, "clear_stop", false, false},
    {Call::kAcquireControl, "acquire_control", false, false},
    {Call::kRenewControl, "renew_control", false, false},
    {Call::kReleaseControl, "release_control", false, false},
    {Call::kReset, "reset", true, false},
};

constexpr const CallSpec& Spec(Call call) { return kCallSpecs[static_cast<int>(call)]; }
constexpr const char* CallName(Call call) { return Spec(call).name; }
std::optional<Call> FindCall(std::string_view name);
// "list_skills, status, ...": for a reply to an unknown call.
std::string KnownCalls();

const char* ModeName(flsd_msgs_Mode mode);
const char* StatusName(flsd_msgs_ReplyStatus status);
const char* TaskStateName(flsd_msgs_TaskState state);

// The project's enums (comm/modes.h) as the IDL's: the same values, so a cast.
inline flsd_msgs_Mode ToIdl(Mode mode) { return static_cast<flsd_msgs_Mode>(mode); }
inline flsd_msgs_TaskState ToIdl(TaskState state) { return static_cast<flsd_msgs_TaskState>(state); }
inline flsd_msgs_ReplyStatus ToIdl(ReplyStatus status) { return static_cast<flsd_msgs_ReplyStatus>(status); }

}  // namespace flsd::dds
