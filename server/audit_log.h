#pragma once
// Who asked the robot to move, and what they were told: one line per motion call, accepted or
// refused, with the sender (its authenticated identity with DDS Security on, and the subject of
// its certificate when a known certificate has that identity's fingerprint; its declared
// client_id without), the call, its arguments and the reply. Lines go to the server log and,
// when a path is given, are appended to that file (mode 0600). Calls dropped by the rate limit
// are only counted (RobotState.requests_dropped): a flood must not become a flood of lines.

#include <string>
#include <unordered_map>

#include "flsd_msgs.h"
#include "server/request_handler.h"

namespace flsd {

class AuditLog {
 public:
  // `certificates`: a folder whose cert.pem files (at any depth: a make_pki.sh folder) name
  // identities' subjects; empty: none. InputError naming the file or folder if the log cannot be
  // opened for appending or a certificate cannot be read.
  AuditLog(const std::string& path, const std::string& certificates);
  ~AuditLog();
  AuditLog(const AuditLog&) = delete;
  AuditLog& operator=(const AuditLog&) = delete;

  // Calls that move or stop the robot or hand control over (not status, list_skills or the
  // lease heartbeat).
  static bool Audited(const char* call);
  // "identity 1a2b...-3c4d... [CN=alice,O=FLSD] (client_id ...) request 7: execute_skill skill 6
  // duration 4.00 s": the request as the log names it, made when it arrives (its reply may come
  // later, from another thread). `identity` is empty without security.
  std::string Describe(const std::string& identity, const flsd_msgs_Request& request) const;
  // Thread-safe: one write per line to a file opened for appending.
  void Record(const std::string& description, const ReplyContent& reply) const;

 private:
  int fd_ = -1;
  std::unordered_map<std::string, std::string> subjects_;  // by subject fingerprint
};

}  // namespace flsd
