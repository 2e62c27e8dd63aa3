#pragma once
// Who asked the robot to move, and what they were told: one line per motion call, accepted or
// refused, with the sender (its authenticated identity with DDS Security on, its declared
// client_id without), the call, its arguments and the reply. Lines go to the server log and,
// when a path is given, are appended to that file (mode 0600). Calls dropped by the rate limit
// are only counted (RobotState.requests_dropped): a flood must not become a flood of lines.

#include <string>

#include "flsd_msgs.h"
#include "server/request_handler.h"

namespace flsd {

class AuditLog {
 public:
  // InputError naming the file if it cannot be opened for appending.
  explicit AuditLog(const std::string& path);
  ~AuditLog();
  AuditLog(const AuditLog&) = delete;
  AuditLog& operator=(const AuditLog&) = delete;

  // Calls that move or stop the robot or hand control over (not status, list_skills or the
  // lease heartbeat).
  static bool Audited(const char* call);
  // "identity 1a2b...-3c4d... (client_id ...) execute_skill skill 6 duration 4.00 s": the request
  // as the log names it, made when it arrives (its reply may come later, from another thread).
  static std::string Describe(const std::string& sender, const flsd_msgs_Request& request);
  // Thread-safe: one write per line to a file opened for appending.
  void Record(const std::string& description, const ReplyContent& reply) const;

 private:
  int fd_ = -1;
};

}  // namespace flsd
