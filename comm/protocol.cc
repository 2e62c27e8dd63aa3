#include "comm/protocol.h"

#include <iterator>

namespace flsd::dds {

static_assert(static_cast<int>(Mode::kIdle) == flsd_msgs_MODE_IDLE);
static_assert(static_cast<int>(Mode::kNavigate) == flsd_msgs_MODE_NAVIGATE);
static_assert(static_cast<int>(Mode::kDamp) == flsd_msgs_MODE_DAMP);
static_assert(static_cast<int>(TaskState::kNone) == flsd_msgs_TASK_NONE);
static_assert(static_cast<int>(TaskState::kSafetyStop) == flsd_msgs_TASK_SAFETY_STOP);
static_assert(static_cast<int>(TaskState::kTimeout) == flsd_msgs_TASK_TIMEOUT);
static_assert(static_cast<int>(ReplyStatus::kOk) == flsd_msgs_STATUS_OK);
static_assert(static_cast<int>(ReplyStatus::kInternal) == flsd_msgs_STATUS_INTERNAL);

constexpr bool SpecsInEnumOrder() {
  for (std::size_t i = 0; i < std::size(kCallSpecs); ++i) {
    if (static_cast<std::size_t>(kCallSpecs[i].call) != i) return false;
  }
  return std::size(kCallSpecs) == static_cast<std::size_t>(Call::kReset) + 1;
}
static_assert(SpecsInEnumOrder(), "kCallSpecs: one spec per call, in the order of the enum");

std::optional<Call> FindCall(std::string_view name) {
  for (const CallSpec& spec : kCallSpecs) {
    if (name == spec.name) return spec.call;
  }
  return std::nullopt;
}

std::string KnownCalls() {
  std::string text;
  for (const CallSpec& spec : kCallSpecs) text += (text.empty() ? "" : ", ") + std::string(spec.name);
  return text;
}

const char* ModeName(flsd_msgs_Mode mode) {
  switch (mode) {
    case flsd_msgs_MODE_IDLE: return "idle";
    case flsd_msgs_MODE_STAND: return "stand";
    case flsd_msgs_MODE_SKILL: return "skill";
    case flsd_msgs_MODE_VELOCITY: return "velocity";
    case flsd_msgs_MODE_NAVIGATE: return "navigate";
    case flsd_msgs_MODE_DAMP: return "damp";
  }
  return "unknown";
}

const char* StatusName(flsd_msgs_ReplyStatus status) {
  switch (status) {
    case flsd_msgs_STATUS_OK: return "ok";
    case flsd_msgs_STATUS_INVALID_ARGUMENT: return "invalid argument";
    case flsd_msgs_STATUS_UNKNOWN_CALL: return "unknown call";
    case flsd_msgs_STATUS_NOT_IN_CONTROL: return "not in control";
    case flsd_msgs_STATUS_NOT_AVAILABLE: return "not available";
    case flsd_msgs_STATUS_SAFETY_STOP: return "safety stop";
    case flsd_msgs_STATUS_DUPLICATE: return "duplicate";
    case flsd_msgs_STATUS_DEADLINE_EXCEEDED: return "deadline exceeded";
    case flsd_msgs_STATUS_INTERNAL: return "internal error";
  }
  return "unknown status";
}

const char* TaskStateName(flsd_msgs_TaskState state) {
  switch (state) {
    case flsd_msgs_TASK_NONE: return "none";
    case flsd_msgs_TASK_RUNNING: return "running";
    case flsd_msgs_TASK_SUCCEEDED: return "succeeded";
    case flsd_msgs_TASK_CANCELLED: return "cancelled";
    case flsd_msgs_TASK_SAFETY_STOP: return "safety stop";
    case flsd_msgs_TASK_PREEMPTED: return "preempted";
    case flsd_msgs_TASK_LEASE_LOST: return "lease lost";
    case flsd_msgs_TASK_NO_PATH: return "no path";
    case flsd_msgs_TASK_TIMEOUT: return "timeout";
  }
  return "unknown";
}

}  // namespace flsd::dds
