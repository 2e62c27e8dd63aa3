// The parts of skillweb's logins that need no network: password hashes, the users file, the
// session store's limit, the rate limiter, and the rule for where skillweb may listen.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <stdexcept>

#include "client/web/credentials.h"
#include "client/web/rate_limiter.h"
#include "client/web/sessions.h"
#include "client/web/users_file.h"
#include "client/web/web_server.h"
#include "core/check.h"
#include "tests/common/test_support.h"

namespace flsd::web {
namespace {

TEST(CredentialsTest, APasswordVerifiesAgainstItsSaltedHashOnly) {
  const std::string hash = HashPassword("correct horse", 10000);
  EXPECT_EQ(hash.rfind("pbkdf2-sha256$10000$", 0), 0u) << hash;
  EXPECT_EQ(PasswordHashError(hash), "");
  EXPECT_TRUE(VerifyPassword("correct horse", hash));
  EXPECT_FALSE(VerifyPassword("correct horsE", hash));
  EXPECT_FALSE(VerifyPassword("", hash));
  // A salt of its own: the same password hashes differently each time.
  EXPECT_NE(HashPassword("correct horse", 10000), hash);
  EXPECT_NE(PasswordHashError("md5$1$aa$bb"), "");
  EXPECT_NE(PasswordHashError("pbkdf2-sha256$100$0011223344556677$" + std::string(64, 'a')), "");  // too few iterations
  EXPECT_FALSE(VerifyPassword("x", "pbkdf2-sha256$10000$zz$00"));
  EXPECT_EQ(RandomHex(32).size(), 64u);
  EXPECT_NE(RandomHex(32), RandomHex(32));
  EXPECT_TRUE(SameSecret("abc", "abc"));
  EXPECT_FALSE(SameSecret("abc", "abd"));
  EXPECT_FALSE(SameSecret("abc", "abcd"));
}

TEST(UsersFileTest, SaveUserWritesAnOwnerOnlyFileThatLoadsBack) {
  const std::string path = testutil::UniqueTempPath("users");
  SaveUser(path, {"alice", Role::kOperator, "alice", HashPassword("pw-alice", 10000)});
  SaveUser(path, {"carol", Role::kObserver, "-", HashPassword("pw-carol", 10000)});
  SaveUser(path, {"alice", Role::kObserver, "alice2", HashPassword("pw-alice-2", 10000)});  // replaces alice
  struct stat st {};
  ASSERT_EQ(stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  const Users users = LoadUsers(path);
  ASSERT_EQ(users.size(), 2u);
  EXPECT_EQ(users.at("alice").role, Role::kObserver);
  EXPECT_EQ(users.at("alice").identity, "alice2");
  EXPECT_TRUE(VerifyPassword("pw-alice-2", users.at("alice").password_hash));
  EXPECT_EQ(users.at("carol").identity, "-");
  chmod(path.c_str(), 0644);
  try {
    LoadUsers(path);
    ADD_FAILURE() << "a users file others may read was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("chmod 600"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

TEST(UsersFileTest, AMalformedLineIsAnErrorNamingTheFileAndLine) {
  const std::string hash = HashPassword("pw", 10000);
  const auto error_of = [](const std::string& text) -> std::string {
    const std::string path = testutil::UniqueTempPath("users");
    std::ofstream(path) << text;
    chmod(path.c_str(), 0600);
    try {
      LoadUsers(path);
      std::remove(path.c_str());
      return "";
    } catch (const InputError& e) {
      std::remove(path.c_str());
      return std::string(e.what()).substr(path.size());
    }
  };
  EXPECT_EQ(error_of("# comment\n\nalice operator alice " + hash + "  # trailing\n"), "");
  EXPECT_EQ(error_of("alice admin alice " + hash + "\n"), ":1: role must be operator or observer, got 'admin'");
  EXPECT_EQ(error_of("\nalice operator alice\n"), ":2: expected NAME ROLE IDENTITY PASSWORD_HASH");
  EXPECT_EQ(error_of("alice operator alice " + hash + "\nalice observer - " + hash + "\n"),
            ":2: user 'alice' appears twice");
  EXPECT_EQ(error_of("al/ice operator alice " + hash + "\n"), ":1: user name 'al/ice' must be 1-40 of [A-Za-z0-9_.-]");
  EXPECT_NE(error_of("alice operator alice plain-password\n").find(":1: expected pbkdf2-sha256$"), std::string::npos);
}

// A page's link without a DDS client.
class NoLink : public PageLink {
 public:
  const std::string& id() const override { return id_; }
  nlohmann::json Command(const std::string&, const std::string&, int& status) override {
    status = 503;
    return nlohmann::json::object();
  }
  nlohmann::json Skills(int& status) override {
    status = 503;
    return nlohmann::json::object();
  }
  std::string NextEvent(uint64_t, uint64_t&, std::chrono::milliseconds) override { return ""; }

 private:
  const std::string id_ = "no-link";
};

TEST(SessionStoreTest, ALoginBeyondTheLimitConnectsNothing) {
  SessionLimits limits;
  limits.max_sessions = 1;
  SessionStore store(limits);
  const User alice{"alice", Role::kOperator, "-", ""};
  int connects = 0;
  const auto connect = [&connects]() -> std::unique_ptr<PageLink> {
    ++connects;
    return std::make_unique<NoLink>();
  };
  // A login while another is still connecting is refused too: the place is taken.
  const std::shared_ptr<Session> first = store.Open(alice, [&]() {
    EXPECT_EQ(store.Open(alice, connect), nullptr);
    return connect();
  });
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(store.Open(alice, connect), nullptr);
  EXPECT_EQ(connects, 1);
  // A link that fails to connect gives its place back.
  store.Close(first->token);
  EXPECT_THROW(store.Open(alice, []() -> std::unique_ptr<PageLink> { throw std::runtime_error("no skilld"); }),
               std::runtime_error);
  EXPECT_NE(store.Open(alice, connect), nullptr);
  EXPECT_EQ(connects, 2);
}

TEST(RateLimiterTest, ABurstThenOnePerInterval) {
  RateLimiter limiter(3, std::chrono::seconds(1));
  const auto t0 = RateLimiter::Clock::now();
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(limiter.Allow("a", t0)) << i;
  EXPECT_FALSE(limiter.Allow("a", t0));
  EXPECT_TRUE(limiter.Allow("b", t0));  // each key has its own bucket
  EXPECT_FALSE(limiter.Allow("a", t0 + std::chrono::milliseconds(900)));
  EXPECT_TRUE(limiter.Allow("a", t0 + std::chrono::milliseconds(1100)));
  EXPECT_FALSE(limiter.Allow("a", t0 + std::chrono::milliseconds(1200)));
}

TEST(ExposureTest, BeyondLoopbackNeedsTlsAndLoginsOrInsecure) {
  ListenOptions listen;
  listen.host = "127.0.0.1";
  EXPECT_EQ(ExposureError(listen, false, false), "");
  listen.host = "0.0.0.0";
  const std::string bare = ExposureError(listen, false, false);
  EXPECT_NE(bare.find("--tls-cert and --tls-key"), std::string::npos) << bare;
  EXPECT_NE(bare.find("--users FILE"), std::string::npos) << bare;
  EXPECT_NE(bare.find("--insecure"), std::string::npos) << bare;
  EXPECT_EQ(ExposureError(listen, false, true), "");
  listen.tls_cert = "cert.pem";
  listen.tls_key = "key.pem";
  EXPECT_NE(ExposureError(listen, false, false).find("--users FILE"), std::string::npos);
  EXPECT_EQ(ExposureError(listen, false, false).find("--tls-cert"), std::string::npos);
  EXPECT_EQ(ExposureError(listen, true, false), "");
}

TEST(ExposureTest, OnlyNumericLoopbackAddressesCountAsLoopback) {
  for (const char* host : {"127.0.0.1", "127.3.2.1", "::1", "localhost"}) EXPECT_TRUE(IsLoopback(host)) << host;
  // A name that merely starts like a loopback address may resolve anywhere.
  for (const char* host : {"127.example.org", "0.0.0.0", "::", "::ffff:127.0.0.1", "10.0.0.1", ""}) {
    EXPECT_FALSE(IsLoopback(host)) << host;
  }
}

}  // namespace
}  // namespace flsd::web
