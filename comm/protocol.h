#pragma once
// What server and client must agree on beyond the IDL types, at the DDS edge: topic names, QoS,
// and the conversion of the project's enums (api/modes.h) and calls (api/calls.h) to the IDL's.

#include "api/calls.h"
#include "api/modes.h"
#include "comm/dds.h"
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

// An IDL value's name for people (api/modes.h's tables); "unknown" outside the enum.
inline const char* ModeName(flsd_msgs_Mode mode) { return Name(static_cast<Mode>(mode)); }
inline const char* StatusName(flsd_msgs_ReplyStatus status) { return Name(static_cast<ReplyStatus>(status)); }
inline const char* TaskStateName(flsd_msgs_TaskState state) { return Name(static_cast<TaskState>(state)); }

// The project's enums (api/modes.h) as the IDL's: the same values, so a cast.
inline flsd_msgs_Mode ToIdl(Mode mode) { return static_cast<flsd_msgs_Mode>(mode); }
inline flsd_msgs_TaskState ToIdl(TaskState state) { return static_cast<flsd_msgs_TaskState>(state); }
inline flsd_msgs_ReplyStatus ToIdl(ReplyStatus status) { return static_cast<flsd_msgs_ReplyStatus>(status); }

}  // namespace flsd::dds
