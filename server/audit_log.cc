#include "server/audit_log.h"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>

#include "comm/dds.h"
#include "comm/protocol.h"
#include "core/check.h"

namespace flsd {

AuditLog::AuditLog(const std::string& path, const std::string& certificates) {
  if (!certificates.empty()) {
    std::error_code error;
    for (std::filesystem::recursive_directory_iterator it(certificates, error), end; !error && it != end;
         it.increment(error)) {
      if (it->path().filename() != "cert.pem") continue;
      try {
        dds::CertificateSubject subject = dds::ReadCertificateSubject(it->path().string());
        subjects_[subject.fingerprint] = std::move(subject.name);
      } catch (const dds::Error& e) {
        throw InputError(std::string("audit_certificates: ") + e.what());
      }
    }
    if (error) throw InputError("audit_certificates: cannot read the folder " + certificates + ": " + error.message());
  }
  if (path.empty()) return;
  fd_ = open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0600);
  if (fd_ < 0) throw InputError("audit_log: cannot open " + path + " for appending: " + std::strerror(errno));
}

AuditLog::~AuditLog() {
  if (fd_ >= 0) close(fd_);
}

bool AuditLog::Audited(const char* call) {
  static const char* const kAudited[] = {"execute_skill", "track_velocity",  "navigate",       "stop",
                                         "stand",         "reset",           "damp",           "clear_stop",
                                         "acquire_control", "release_control"};
  if (call == nullptr) return false;
  for (const char* c : kAudited) {
    if (std::strcmp(call, c) == 0) return true;
  }
  return false;
}

std::string AuditLog::Describe(const std::string& identity, const flsd_msgs_Request& r) const {
  const std::string call = r.call != nullptr ? r.call : "";
  const std::string client_id = r.header.client_id != nullptr ? r.header.client_id : "";
  std::string sender = "client_id " + client_id + " (unauthenticated)";
  if (!identity.empty()) {
    const auto subject = subjects_.find(identity.substr(0, 12));
    sender = "identity " + identity + (subject != subjects_.end() ? " [" + subject->second + "]" : "") +
             " (client_id " + client_id + ")";
  }
  char args[160] = "";
  if (call == "execute_skill") {
    std::snprintf(args, sizeof args, " skill %d duration %.2f s", r.skill, r.duration);
  } else if (call == "track_velocity") {
    std::snprintf(args, sizeof args, " velocity (%.2f, %.2f, %.2f) duration %.2f s", r.velocity[0], r.velocity[1],
                  r.velocity[2], r.duration);
  } else if (call == "navigate") {
    std::snprintf(args, sizeof args, " goal (%.2f, %.2f) duration %.2f s map %zu bytes", r.goal[0], r.goal[1],
                  r.duration, r.map_yaml != nullptr ? std::strlen(r.map_yaml) : 0);
  }
  return sender + " request " + std::to_string(r.header.request_id) + ": " + call + args;
}

void AuditLog::Record(const std::string& description, const ReplyContent& reply) const {
  const std::string outcome = std::string(reply.status == ReplyStatus::kOk ? "accepted" : "refused") + " (" +
                              Name(reply.status) + ": " + reply.message + ")";
  spdlog::info("audit: {} -> {}", description, outcome);
  if (fd_ < 0) return;
  char when[32];
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", &utc);
  const std::string line = std::string(when) + " " + description + " -> " + outcome + "\n";
  // O_APPEND makes each write land whole at the end, whichever thread writes it.
  if (write(fd_, line.data(), line.size()) != static_cast<ssize_t>(line.size())) {
    spdlog::error("audit: could not append to the audit log: {}", std::strerror(errno));
  }
}

}  // namespace flsd
