// skillweb's routes over real HTTPS on loopback, against a real skilld: logins right and wrong,
// an observer who cannot command, CSRF tokens and origins, one lease per page, logout, rate
// limits, the audit lines, and the refusal to serve beyond loopback without HTTPS and logins.

#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/client/web/page_session.h"
#include "tests/client/web/skillweb_process.h"
#include "tests/common/skilld_fixture.h"

namespace flsd {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testutil::PageSession;
using testutil::UniqueTempPath;

class SkillwebHttpsTest : public testutil::SkilldFixture {
 protected:
  // Operators alice and bob, observer carol.
  static void SetUpTestSuite() {
    dir_ = (fs::temp_directory_path() / ("flsd_web_https_" + std::to_string(getpid()))).string();
    fs::create_directories(dir_);
    testutil::MakeHttpsLogins(dir_, {{"alice", "operator"}, {"bob", "operator"}, {"carol", "observer"}});
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string Password(const std::string& name) { return testutil::TestPassword(name); }

  testutil::Skillweb Start() {
    std::vector<std::string> args = {"--domain", std::to_string(domain_), "--partition", partition_};
    for (const std::string& a : testutil::HttpsLoginArgs(dir_)) args.push_back(a);
    return testutil::StartSkillweb(args, UniqueTempPath("skillweb.log"));
  }

  static inline std::string dir_;
};

json Body(const httplib::Result& r) { return r ? json::parse(r->body) : json(); }

TEST_F(SkillwebHttpsTest, RefusesToServeBeyondLoopbackWithoutHttpsAndLogins) {
  const auto [code, output] = testutil::RunProgram(testutil::BinaryPath("skillweb"), {"--host", "0.0.0.0", "--port", "0"},
                                                   UniqueTempPath("skillweb_open.log"));
  EXPECT_EQ(code, 1);
  EXPECT_NE(output.find("--host 0.0.0.0 serves beyond loopback"), std::string::npos) << output;
  EXPECT_NE(output.find("--tls-cert and --tls-key (HTTPS) and --users FILE"), std::string::npos) << output;
  EXPECT_NE(output.find("or --insecure"), std::string::npos) << output;
  const auto [tls_code, tls_output] = testutil::RunProgram(
      testutil::BinaryPath("skillweb"),
      {"--host", "0.0.0.0", "--port", "0", "--tls-cert", dir_ + "/cert.pem", "--tls-key", dir_ + "/key.pem"},
      UniqueTempPath("skillweb_tls_only.log"));
  EXPECT_EQ(tls_code, 1);
  EXPECT_NE(tls_output.find("give --users FILE (a login per page)"), std::string::npos) << tls_output;
}

TEST_F(SkillwebHttpsTest, LoginsRolesCsrfLeasesAndAudit) {
  StartServer();
  const testutil::Skillweb web = Start();
  ASSERT_EQ(web.url.rfind("https://127.0.0.1:", 0), 0u) << web.url;

  PageSession stranger(web.url);
  EXPECT_EQ(Body(stranger.Get("/api/session")), (json{{"logged_in", false}, {"logins", true}}));
  EXPECT_EQ(stranger.Get("/api/events")->status, 401);
  EXPECT_EQ(stranger.Command("stand")->status, 401);
  EXPECT_EQ(stranger.Login("alice", "not-her-password")->status, 401);
  EXPECT_EQ(stranger.Login("mallory", "any-password")->status, 401);
  EXPECT_EQ(stranger.Get("/")->status, 200);  // the page itself, with its login form

  PageSession alice(web.url);
  const httplib::Result login = alice.Login("alice", Password("alice"));
  ASSERT_TRUE(login && login->status == 200) << (login ? login->body : "no answer");
  const std::string cookie = login->get_header_value("Set-Cookie");
  EXPECT_TRUE(std::regex_search(cookie, std::regex("^skillweb_session=[0-9a-f]{64}; Path=/; Max-Age=43200; "
                                                   "HttpOnly; SameSite=Strict; Secure$")))
      << cookie;
  const json session = Body(login);
  EXPECT_EQ(session["role"], "operator");
  EXPECT_EQ(session["can_command"], true);
  EXPECT_EQ(alice.csrf().size(), 64u);

  // No token, a wrong one, or another site's origin: refused before anything reaches skilld.
  const std::string none, wrong(64, '0');
  EXPECT_EQ(alice.Command("stand", "{}", &none)->status, 403);
  EXPECT_EQ(alice.Command("stand", "{}", &wrong)->status, 403);
  EXPECT_EQ(alice.Command("stand", "{}", nullptr, "https://evil.example")->status, 403);
  // The right token: skilld stands the robot (once it is up), with the lease of alice's page.
  json stand;
  for (int i = 0; i < 40 && stand["ok"] != true; ++i) {
    stand = Body(alice.Command("stand"));
    if (stand["ok"] != true) std::this_thread::sleep_for(std::chrono::milliseconds(250));
  }
  EXPECT_EQ(stand["ok"], true) << stand.dump() << server_->Log();

  // An observer watches the state and cannot command.
  PageSession carol(web.url);
  const json observer = Body(carol.Login("carol", Password("carol")));
  EXPECT_EQ(observer["role"], "observer");
  EXPECT_EQ(observer["can_command"], false);
  const httplib::Result refused = carol.Command("stand");
  EXPECT_EQ(refused->status, 403);
  EXPECT_NE(refused->body.find("observer: may watch, not command"), std::string::npos) << refused->body;
  EXPECT_NE(carol.FirstEvent(std::chrono::seconds(10)).find("\"backend\":\"sim\""), std::string::npos);

  // Another page is another client: skilld refuses it the lease alice's page holds.
  PageSession bob(web.url);
  ASSERT_EQ(bob.Login("bob", Password("bob"))->status, 200);
  const json second = Body(bob.Command("stand"));
  EXPECT_EQ(second["status"], "not in control") << second.dump();
  EXPECT_NE(second["message"].get<std::string>().find(session["client_id"].get<std::string>()), std::string::npos)
      << second.dump();

  // Logout closes alice's session and its client, which gives the lease back.
  EXPECT_EQ(alice.Command("logout")->status, 200);
  EXPECT_EQ(Body(alice.Get("/api/session"))["logged_in"], false);
  EXPECT_EQ(alice.Get("/api/info")->status, 401);
  EXPECT_EQ(Body(bob.Command("stand"))["ok"], true);

  const std::string log = web.process->Log();
  const std::string id = session["client_id"];
  EXPECT_NE(log.find("from 127.0.0.1: alice (operator, client " + id + "): stand {} -> ok: "), std::string::npos) << log;
  EXPECT_NE(log.find("alice (operator, client " + id + "): stand -> refused: missing or wrong CSRF token"),
            std::string::npos) << log;
  EXPECT_NE(log.find("carol (observer, client " + observer["client_id"].get<std::string>() +
                     "): stand -> refused: an observer does not command"),
            std::string::npos) << log;
  EXPECT_NE(log.find("login: refused for user 'mallory'"), std::string::npos) << log;
  EXPECT_NE(log.find("bob (operator, client "), std::string::npos) << log;
}

TEST_F(SkillwebHttpsTest, LoginAttemptsAndCommandsAreRateLimited) {
  StartServer();
  const testutil::Skillweb web = Start();
  PageSession alice(web.url);
  ASSERT_EQ(alice.Login("alice", Password("alice"))->status, 200);
  // A page's commands: a burst of 20, then 5 a second.
  int accepted = 0, limited = 0;
  for (int i = 0; i < 40; ++i) {
    const int status = alice.Command("release_control")->status;
    accepted += status == 200;
    limited += status == 429;
  }
  EXPECT_GE(accepted, 20);
  EXPECT_GE(limited, 10);
  EXPECT_EQ(accepted + limited, 40);

  // Logins from one address: 5 at once (alice's was the first), then one every 10 s.
  PageSession guesser(web.url);
  std::vector<int> statuses;
  while (statuses.size() < 10 && (statuses.empty() || statuses.back() != 429)) {
    statuses.push_back(guesser.Login("alice", "guess-" + std::to_string(statuses.size()))->status);
  }
  ASSERT_EQ(statuses.back(), 429);
  EXPECT_GE(statuses.size(), 5u);
  for (std::size_t i = 0; i + 1 < statuses.size(); ++i) EXPECT_EQ(statuses[i], 401) << i;
  EXPECT_EQ(guesser.Login("alice", Password("alice"))->status, 429);  // the right password waits too
}

}  // namespace
}  // namespace flsd
