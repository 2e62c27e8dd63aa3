// skillweb against skilld with DDS Security on. The open page (no logins) with an operator's
// identity (--security) streams the state and commands; without credentials it does neither.
// With logins, HTTPS and --pki, one skillweb serves a page per login, each a participant with its
// user's identity (in a page agent process: Cyclone keeps one identity per process): the
// operator's page commands, the observer's streams the state and cannot command. The test
// speaks HTTP(S) only and makes no DDS entity: Cyclone keeps one security configuration per process.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/client/web/page_session.h"
#include "tests/client/web/skillweb_process.h"
#include "tests/common/skilld_fixture.h"

namespace flsd {
namespace {

namespace fs = std::filesystem;
using testutil::PageSession;
using testutil::UniqueTempPath;

class SkillwebSecurityTest : public testutil::SkilldFixture {
 protected:
  static void SetUpTestSuite() {
    pki_ = (fs::temp_directory_path() / ("flsd_web_pki_" + std::to_string(getpid()))).string();
    const std::string make = "bash " FLSD_SOURCE_DIR "/scripts/make_pki.sh " + pki_ + " --operators op --observers obs > /dev/null";
    ASSERT_EQ(std::system(make.c_str()), 0);
    testutil::MakeHttpsLogins(pki_, {{"op", "operator"}, {"obs", "observer"}}, true);
  }
  static void TearDownTestSuite() { fs::remove_all(pki_); }

  testutil::Skillweb Start(const std::string& tag, std::vector<std::string> extra) {
    std::vector<std::string> args = {"--domain", std::to_string(domain_), "--partition", partition_};
    args.insert(args.end(), extra.begin(), extra.end());
    return testutil::StartSkillweb(args, UniqueTempPath(tag + ".log"));
  }

  // The first state event the page gets; the security handshake takes a moment: up to 20 s.
  static std::string AwaitEvent(PageSession& page) {
    std::string event;
    for (int i = 0; i < 20 && event.empty(); ++i) event = page.FirstEvent(std::chrono::seconds(1));
    return event;
  }

  static inline std::string pki_;
};

TEST_F(SkillwebSecurityTest, AnOperatorsIdentityStreamsAndCommandsAndNoCredentialsDoNeither) {
  StartServer("sim", pki_ + "/skilld/security.yaml");
  const testutil::Skillweb op = Start("skillweb_op", {"--security", pki_ + "/op/security.yaml"});
  const testutil::Skillweb none = Start("skillweb_none", {});
  ASSERT_FALSE(op.url.empty() || none.url.empty());

  PageSession op_page(op.url), none_page(none.url);
  ASSERT_EQ(op_page.Session()->status, 200);
  ASSERT_EQ(none_page.Session()->status, 200);
  EXPECT_NE(AwaitEvent(op_page).find("\"backend\":\"sim\""), std::string::npos) << op.process->Log() << server_->Log();
  EXPECT_NE(op_page.Command("stand")->body.find("\"ok\":true"), std::string::npos);

  EXPECT_EQ(none_page.FirstEvent(std::chrono::seconds(2)), "");
  EXPECT_NE(none_page.Command("stand")->body.find("\"status\":\"no reply\""), std::string::npos);
}

TEST_F(SkillwebSecurityTest, EachLoginIsAParticipantWithItsUsersIdentity) {
  StartServer("sim", pki_ + "/skilld/security.yaml");
  std::vector<std::string> args = testutil::HttpsLoginArgs(pki_);
  args.insert(args.end(), {"--pki", pki_});
  const testutil::Skillweb web = Start("skillweb_logins", args);
  ASSERT_FALSE(web.url.empty());

  PageSession op(web.url), obs(web.url);
  const httplib::Result op_login = op.Login("op", testutil::TestPassword("op"));
  ASSERT_TRUE(op_login && op_login->status == 200) << (op_login ? op_login->body : "") << web.process->Log();
  const httplib::Result obs_login = obs.Login("obs", testutil::TestPassword("obs"));
  ASSERT_TRUE(obs_login && obs_login->status == 200) << (obs_login ? obs_login->body : "") << web.process->Log();
  // Authenticated identities: the subject's fingerprint, then the participant's own part.
  const std::string op_id = nlohmann::json::parse(op_login->body)["client_id"];
  const std::string obs_id = nlohmann::json::parse(obs_login->body)["client_id"];
  EXPECT_TRUE(std::regex_match(op_id, std::regex("[0-9a-f]{12}-[0-9a-f]{12}"))) << op_id;
  EXPECT_NE(op_id.substr(0, 12), obs_id.substr(0, 12)) << "two users, one certificate subject";

  EXPECT_NE(AwaitEvent(op).find("\"backend\":\"sim\""), std::string::npos) << web.process->Log() << server_->Log();
  EXPECT_NE(AwaitEvent(obs).find("\"backend\":\"sim\""), std::string::npos) << web.process->Log();
  nlohmann::json stand;
  for (int i = 0; i < 20 && stand["ok"] != true; ++i) {
    stand = nlohmann::json::parse(op.Command("stand")->body);
    if (stand["ok"] != true) std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  EXPECT_EQ(stand["ok"], true) << stand.dump() << server_->Log();
  EXPECT_EQ(obs.Command("stand")->status, 403);
  // skilld's own audit names the operator's page by its identity.
  EXPECT_NE(server_->Log().find("identity " + op_id), std::string::npos) << server_->Log();
}

}  // namespace
}  // namespace flsd
