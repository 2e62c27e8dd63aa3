// The audit log: which calls it records, how a line names the sender, the call and its arguments,
// and the file it appends to.

#include "server/audit_log.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;
using ::testing::MatchesRegex;

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

flsd_msgs_Request Request(const char* client_id, uint64_t id, const char* call) {
  flsd_msgs_Request r{};
  r.header.client_id = const_cast<char*>(client_id);
  r.header.request_id = id;
  r.call = const_cast<char*>(call);
  r.map_yaml = const_cast<char*>("");
  return r;
}

TEST(AuditLogTest, RecordsCallsThatMoveOrStopTheRobotOrHandOverControl) {
  for (const char* call : {"execute_skill", "track_velocity", "navigate", "stop", "stand", "reset", "damp",
                           "clear_stop", "acquire_control", "release_control"}) {
    EXPECT_TRUE(AuditLog::Audited(call)) << call;
  }
  for (const char* call : {"status", "list_skills", "renew_control", "fly", ""}) EXPECT_FALSE(AuditLog::Audited(call));
  EXPECT_FALSE(AuditLog::Audited(nullptr));
}

TEST(AuditLogTest, ALineNamesTheSenderTheCallItsArgumentsAndTheReply) {
  const std::string path = testutil::UniqueTempPath("audit.log");
  std::remove(path.c_str());
  {
    const AuditLog log(path, "");
    flsd_msgs_Request skill = Request("alice", 7, "execute_skill");
    skill.skill = 6;
    skill.duration = 4.0;
    ReplyContent accepted;
    accepted.message = "skill 6 for 4.00 s accepted";
    log.Record(log.Describe("", skill), accepted);
    flsd_msgs_Request velocity = Request("0123456789ab-cdef01234567", 8, "track_velocity");
    velocity.velocity[0] = 0.4;
    velocity.velocity[2] = -1.0;
    velocity.duration = 2.5;
    ReplyContent refused;
    refused.status = ReplyStatus::kNotInControl;
    refused.message = "control is held by alice";
    log.Record(log.Describe("0123456789ab-cdef01234567", velocity), refused);
  }
  std::istringstream lines(ReadText(path));
  std::string first, second;
  std::getline(lines, first);
  std::getline(lines, second);
  EXPECT_THAT(first, MatchesRegex("[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9:]{8}Z client_id alice \\(unauthenticated\\) "
                                  "request 7: execute_skill skill 6 duration 4\\.00 s -> accepted \\(ok: skill 6 "
                                  "for 4\\.00 s accepted\\)"));
  EXPECT_THAT(second, HasSubstr("Z identity 0123456789ab-cdef01234567 (client_id 0123456789ab-cdef01234567) request 8: "
                                "track_velocity velocity (0.40, 0.00, -1.00) duration 2.50 s -> refused (not in "
                                "control: control is held by alice)"));
  struct stat st {};
  ASSERT_EQ(stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  std::remove(path.c_str());
}

TEST(AuditLogTest, BadPathsAreNamed) {
  EXPECT_THAT(testutil::InputErrorMessage([] { AuditLog("/nonexistent/dir/audit.log", ""); }),
              HasSubstr("audit_log: cannot open /nonexistent/dir/audit.log for appending: "));
  const std::string dir = testutil::UniqueTempPath("certs");
  std::filesystem::create_directories(dir + "/alice");
  std::ofstream(dir + "/alice/cert.pem") << "not a certificate\n";
  EXPECT_EQ(testutil::InputErrorMessage([&] { AuditLog("", dir); }),
            "audit_certificates: " + dir + "/alice/cert.pem holds no PEM certificate");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace flsd
