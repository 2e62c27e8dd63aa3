#include "client/types.h"

#include <cmath>

#include "comm/protocol.h"

namespace flsd {

const char* Name(ReplyStatus status) {
  if (status == ReplyStatus::kNoReply) return "no reply";
  return dds::StatusName(dds::ToIdl(status));
}

const char* Name(Mode mode) { return dds::ModeName(static_cast<flsd_msgs_Mode>(mode)); }

const char* Name(TaskState state) { return dds::TaskStateName(static_cast<flsd_msgs_TaskState>(state)); }

std::string Reply::Describe() const {
  if (!answered()) return "no reply from skilld";
  std::string text = std::string(Name(status)) + ": " + message;
  if (!safety_report.empty()) text += " [safety: " + safety_report + "]";
  return text;
}

double StateReport::yaw() const {
  const double w = orientation[0], x = orientation[1], y = orientation[2], z = orientation[3];
  return std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
}

}  // namespace flsd
