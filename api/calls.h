#pragma once
// The calls a client can make of skilld, with no DDS type in sight: the server's request handler
// and controller, the clients and skillctl name them from this one table. On the wire a request
// carries the call's name (comm/protocol.h), so that an unknown call stays answerable.

#include <optional>
#include <string>
#include <string_view>

namespace flsd {

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
  bool long_running;   // answered once accepted, not when done; progress and result on the state topic
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

}  // namespace flsd
