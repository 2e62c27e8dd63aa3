// skillweb's routes in this process, with logins whose page agents are scripts: no skilld, no DDS.
// A login whose client cannot connect is refused without the reason, which goes to the log.

#include "client/web/web_app.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "client/web/credentials.h"
#include "tests/client/web/page_session.h"
#include "tests/common/test_support.h"

namespace flsd::web {
namespace {

namespace fs = std::filesystem;

// --pki's folder for user alice: a security.yaml whose files are readable (and not checked further),
// and a page agent script that refuses with `reason`.
class FakePki {
 public:
  explicit FakePki(const std::string& reason) : dir_(testutil::UniqueTempPath("pki")) {
    fs::create_directories(dir_ + "/alice");
    std::string yaml = "security:\n  enabled: true\n";
    for (const char* key : {"identity_ca", "identity_certificate", "private_key", "permissions_ca", "governance",
                            "permissions"}) {
      const std::string file = dir_ + "/alice/" + key;
      std::ofstream(file) << "not checked here\n";
      chmod(file.c_str(), 0600);
      yaml += std::string("  ") + key + ": " + file + "\n";
    }
    std::ofstream(dir_ + "/alice/security.yaml") << yaml;
    std::ofstream(agent()) << "#!/bin/sh\necho 'X " << reason << "'\n";
    chmod(agent().c_str(), 0700);
  }
  ~FakePki() { fs::remove_all(dir_); }
  const std::string& dir() const { return dir_; }
  std::string agent() const { return dir_ + "/agent.sh"; }

 private:
  std::string dir_;
};

TEST(WebAppTest, ALoginWhoseClientCannotConnectIsRefusedWithoutTheReason) {
  const std::string reason = "dds_create_participant: /secret/path/key.pem is not a key";
  const FakePki pki(reason);
  WebAppOptions options;
  options.users = Users{{"alice", User{"alice", Role::kOperator, "alice", HashPassword("alice-password", 10000)}}};
  options.pki_dir = pki.dir();
  options.agent_program = pki.agent();
  WebApp web(options);
  ListenOptions listen;
  listen.port = 0;
  const int port = web.Listen(listen);

  testutil::PageSession page("http://127.0.0.1:" + std::to_string(port) + "/");
  testing::internal::CaptureStderr();
  const httplib::Result login = page.Login("alice", "alice-password");
  const std::string log = testing::internal::GetCapturedStderr();
  ASSERT_TRUE(login);
  EXPECT_EQ(login->status, 503);
  EXPECT_EQ(nlohmann::json::parse(login->body)["message"], "cannot connect this page to skilld: skillweb's log says why");
  EXPECT_EQ(login->body.find("secret"), std::string::npos) << login->body;
  EXPECT_NE(log.find("login: user 'alice': cannot connect its client: " + reason), std::string::npos) << log;
}

}  // namespace
}  // namespace flsd::web
