// skillweb against skilld with DDS Security on: with an operator's identity (--security) the page's
// stream has the state and its calls move the robot; without credentials it has neither. The test
// speaks HTTP only and makes no DDS entity: Cyclone keeps one security configuration per process.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "tests/client/web/http_exchange.h"
#include "tests/client/web/skillweb_process.h"
#include "tests/common/skilld_fixture.h"

namespace flsd {
namespace {

namespace fs = std::filesystem;
using testutil::HttpExchange;
using testutil::UniqueTempPath;

class SkillwebSecurityTest : public testutil::SkilldFixture {
 protected:
  static void SetUpTestSuite() {
    pki_ = (fs::temp_directory_path() / ("flsd_web_pki_" + std::to_string(getpid()))).string();
    const std::string make = "bash " FLSD_SOURCE_DIR "/scripts/make_pki.sh " + pki_ + " --operators op --observers '' > /dev/null";
    ASSERT_EQ(std::system(make.c_str()), 0);
  }
  static void TearDownTestSuite() { fs::remove_all(pki_); }

  testutil::Skillweb Start(const std::string& tag, std::vector<std::string> extra) {
    std::vector<std::string> args = {"--domain", std::to_string(domain_), "--partition", partition_};
    args.insert(args.end(), extra.begin(), extra.end());
    return testutil::StartSkillweb(args, UniqueTempPath(tag + ".log"));
  }

  static std::string Post(int port, const std::string& call) {
    return HttpExchange(port, "POST /api/" + call + " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                                                    "Content-Length: 2\r\n\r\n{}");
  }

  // The first state event on the stream, or "" if none comes within `timeout`.
  static std::string FirstEvent(int port, std::chrono::seconds timeout) {
    const std::string events = HttpExchange(port, "GET /api/events HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n", "data: {",
                                            std::chrono::duration_cast<std::chrono::milliseconds>(timeout));
    return events.find("data: {") == std::string::npos ? "" : events;
  }

  static inline std::string pki_;
};

TEST_F(SkillwebSecurityTest, AnOperatorsIdentityStreamsAndCommandsAndNoCredentialsDoNeither) {
  StartServer("sim", pki_ + "/skilld/security.yaml");
  const testutil::Skillweb op = Start("skillweb_op", {"--security", pki_ + "/op/security.yaml"});
  const testutil::Skillweb none = Start("skillweb_none", {});
  ASSERT_FALSE(op.url.empty() || none.url.empty());

  // The security handshake takes a moment: wait for the operator's stream, up to 20 s.
  std::string event;
  for (int i = 0; i < 20 && event.empty(); ++i) event = FirstEvent(op.port, std::chrono::seconds(1));
  EXPECT_NE(event.find("\"backend\":\"sim\""), std::string::npos) << op.process->Log() << server_->Log();
  EXPECT_NE(Post(op.port, "stand").find("\"ok\":true"), std::string::npos);

  EXPECT_EQ(FirstEvent(none.port, std::chrono::seconds(2)), "");
  EXPECT_NE(Post(none.port, "stand").find("\"status\":\"no reply\""), std::string::npos);
}

}  // namespace
}  // namespace flsd
