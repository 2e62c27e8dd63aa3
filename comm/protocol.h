#pragma once
// What server and client must agree on beyond the IDL types: topic names, QoS, and the names of
// the enums for people.

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

const char* ModeName(flsd_msgs_Mode mode);
const char* StatusName(flsd_msgs_ReplyStatus status);
const char* TaskStateName(flsd_msgs_TaskState state);

}  // namespace flsd::dds
