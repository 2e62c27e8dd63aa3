// skilld with DDS Security on, against real Cyclone with its security plugins on loopback, and
// certificates that scripts/make_pki.sh makes in a temporary folder: who may command, who may
// only watch, who is shut out, and why a client_id is no longer enough to hold the lease.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "client/client.h"
#include "core/config.h"
#include "tests/common/random_requests.h"
#include "tests/common/raw_dds_client.h"
#include "tests/common/skilld_fixture.h"

namespace flsd {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;
using ::testing::Not;
using fuzz::RawClient;
using fuzz::RawReply;
using fuzz::RawRequest;
using fuzz::RawState;
namespace fs = std::filesystem;

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Whether a line of `text` has `first` and, after it, `then`.
bool HasLine(const std::string& text, const std::string& first, const std::string& then) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t at = line.find(first);
    if (at != std::string::npos && line.find(then, at + first.size()) != std::string::npos) return true;
  }
  ADD_FAILURE() << "no line has '" << first << "' and then '" << then << "' in:\n" << text;
  return false;
}

// Runs a shell command; returns its exit code, and its output in `output`.
int Shell(const std::string& command, std::string* output = nullptr) {
  const std::string log = fs::temp_directory_path() / ("flsd_security_shell_" + std::to_string(getpid()) + ".log");
  const int status = std::system((command + " > " + log + " 2>&1").c_str());
  if (output != nullptr) *output = ReadText(log);
  std::remove(log.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class SkilldSecurityTest : public testutil::SkilldFixture {
 protected:
  // Two deployments: ours, and one of another CA; and an operator of ours whose certificate
  // expired in 2020 (openssl ca, the one openssl command that signs with dates in the past).
  static void SetUpTestSuite() {
    pki_ = fs::temp_directory_path() / ("flsd_pki_" + std::to_string(getpid()));
    const std::string script = "bash " FLSD_SOURCE_DIR "/scripts/make_pki.sh ";
    std::string out;
    ASSERT_EQ(Shell(script + pki_ + "/ours --operators 'alice bob' --observers carol", &out), 0) << out;
    ASSERT_EQ(Shell(script + pki_ + "/theirs --operators mallory --observers ''", &out), 0) << out;
    const std::string expired = pki_ + "/expired";
    fs::create_directories(expired);
    const std::string ca = pki_ + "/ours";
    ASSERT_EQ(Shell("cd " + expired + " && umask 077 && openssl ecparam -name prime256v1 -genkey -noout -out key.pem && "
                    "openssl req -new -key key.pem -subj /O=FLSD/CN=alice -out req.csr && touch index.txt && "
                    "echo 01 > serial && printf '[ca]\\ndefault_ca=d\\n[d]\\ndatabase=index.txt\\nnew_certs_dir=.\\n"
                    "serial=serial\\npolicy=p\\ndefault_md=sha256\\n[p]\\nO=supplied\\nCN=supplied\\n' > ca.cnf && "
                    "openssl ca -batch -config ca.cnf -cert " + ca + "/ca.pem -keyfile " + ca +
                    "/private/ca_key.pem -in req.csr -out cert.pem -startdate 20200101000000Z -enddate 20200201000000Z",
                    &out), 0) << out;
  }
  static void TearDownTestSuite() { fs::remove_all(pki_); }

  static dds::SecurityConfig Identity(const std::string& deployment, const std::string& name) {
    return LoadConfigSection<dds::SecurityConfig>(pki_ + "/" + deployment + "/" + name + "/security.yaml", "security");
  }

  // skilld as ours/skilld, with a lease that cannot lapse while a test runs, and an audit file.
  void SetUp() override {
    SkilldFixture::SetUp();
    audit_path_ = testutil::UniqueTempPath("audit.log");
    config_ = std::make_unique<testutil::TempFile>(
        ".yaml", ReadText(pki_ + "/ours/skilld/security.yaml") + "lease_timeout: 30\naudit_log: " + audit_path_ +
                         "\naudit_certificates: " + pki_ + "/ours\n");
    StartServer("sim", config_->path());
  }
  void TearDown() override { std::remove(audit_path_.c_str()); }

  // Cyclone keeps one security configuration per domain and process, its first participant's:
  // each identity needs a process of its own. So this process makes no DDS entity: `body` runs
  // in a fork (Cyclone not yet started), and its result, or the exception it threw, comes back
  // as text with what it wrote on stderr.
  struct ChildResult {
    std::string out, err;
  };
  template <class F>
  ChildResult InChild(F&& body) {
    const std::string out_path = testutil::UniqueTempPath("child" + std::to_string(children_) + ".out");
    const std::string err_path = testutil::UniqueTempPath("child" + std::to_string(children_++) + ".err");
    const pid_t pid = fork();
    if (pid == 0) {
      alarm(120);  // a stuck child must not hang the suite
      const int err = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      dup2(err, 2);
      std::string out;
      try {
        out = body();
      } catch (const std::exception& e) {
        out = std::string("exception: ") + e.what();
      }
      std::ofstream(out_path) << out;
      std::fflush(stderr);
      _exit(0);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    ChildResult r{ReadText(out_path), ReadText(err_path)};
    std::remove(out_path.c_str());
    std::remove(err_path.c_str());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the child died: " << status << "\n" << r.err;
    return r;
  }

  // A participant with these credentials (none: no security), seeing the server within 20 s.
  std::unique_ptr<RawClient> Connect(const dds::SecurityConfig& security) const {
    auto raw = std::make_unique<RawClient>(domain_, partition_, security);
    if (!raw->WaitForServer(std::chrono::seconds(20))) throw std::runtime_error("no answer from skilld");
    return raw;
  }

  RawReply Call(RawClient& raw, const std::string& client_id, const std::string& call) {
    RawRequest r;
    r.client_id = client_id;
    r.request_id = ++next_id_;
    r.call = call;
    if (call == "execute_skill") {
      r.skill = 1;
      r.duration = 2.0;
    }
    const std::optional<RawReply> reply = raw.Call(r);
    if (!reply) throw std::runtime_error(call + " from " + client_id + " was not answered");
    return *reply;
  }

  // "state" if a state sample reaches these credentials within `wait`, "answered" if the server
  // answers them, or "shut out".
  std::string Reach(const dds::SecurityConfig& security, std::chrono::milliseconds wait) {
    return InChild([&] {
      RawClient raw(domain_, partition_, security);
      if (raw.WaitForState([](const RawState&) { return true; }, wait)) return std::string("state");
      return std::string(raw.WaitForServer(std::chrono::milliseconds(500)) ? "answered" : "shut out");
    }).out;
  }

  // An operator's child: takes control and stands the robot; returns its identity.
  std::string AcquireAndStand(const std::string& name) {
    return InChild([&] {
      const std::unique_ptr<RawClient> raw = Connect(Identity("ours", name));
      const std::string id = raw->identity();
      for (const char* call : {"acquire_control", "stand"}) {
        const RawReply r = Call(*raw, id, call);
        if (r.status != flsd_msgs_STATUS_OK) return std::string(call) + " refused: " + r.message;
      }
      if (!raw->WaitForState([](const RawState& s) { return s.mode == flsd_msgs_MODE_STAND; }, 5s)) {
        return std::string("never stood");
      }
      return id;
    }).out;
  }

  static inline std::string pki_;
  std::string audit_path_;
  std::unique_ptr<testutil::TempFile> config_;
  uint64_t next_id_ = static_cast<uint64_t>(dds_time());
  int children_ = 0;
};

TEST_F(SkilldSecurityTest, MakePkiWritesKeysForTheOwnerOnlyAndNeverIntoTheRepository) {
  for (const char* key : {"/ours/private/ca_key.pem", "/ours/skilld/key.pem", "/ours/alice/key.pem"}) {
    struct stat st {};
    ASSERT_EQ(stat((pki_ + key).c_str(), &st), 0) << key;
    EXPECT_EQ(st.st_mode & 0777, 0600u) << key;
  }
  std::string out;
  EXPECT_EQ(Shell("openssl smime -verify -in " + pki_ + "/ours/carol/permissions.p7s -CAfile " + pki_ + "/ours/ca.pem",
                  &out), 0) << out;
  EXPECT_THAT(out, HasSubstr("<subject_name>CN=carol,O=FLSD</subject_name>"));
  EXPECT_THAT(out, HasSubstr("<topic>flsd/state</topic>"));
  EXPECT_THAT(out, Not(HasSubstr("<publish>")));
  EXPECT_EQ(Shell("bash " FLSD_SOURCE_DIR "/scripts/make_pki.sh " FLSD_SOURCE_DIR "/build/pki", &out), 2);
  EXPECT_THAT(out, HasSubstr("is inside the repository"));
  EXPECT_FALSE(fs::exists(FLSD_SOURCE_DIR "/build/pki"));
}

TEST_F(SkilldSecurityTest, AnOperatorCommandsAndAnObserverOnlyReadsState) {
  const std::string alice = AcquireAndStand("alice");
  ASSERT_THAT(alice, ::testing::MatchesRegex("[0-9a-f]{12}-[0-9a-f]{12}")) << server_->Log();
  const ChildResult carol = InChild([&] {
    std::string out;
    try {  // her permissions do not let her write requests: Cyclone refuses the topic itself
      RawClient raw(domain_, partition_, Identity("ours", "carol"));
      out = "created a request writer; ";
    } catch (const dds::Error& e) {
      out = std::string(e.what()) + "; ";
    }
    // But she reads the state, and so learns who holds control.
    dds::Domain domain(domain_, partition_, Identity("ours", "carol"));
    dds::Reader<flsd_msgs_RobotState> states(domain, flsd_msgs_RobotState_desc, dds::kStateTopic, dds::kStateQos);
    std::string controller;
    const auto until = std::chrono::steady_clock::now() + 20s;
    while (controller.empty() && std::chrono::steady_clock::now() < until) {
      states.Wait(100ms);
      states.Take([&](const flsd_msgs_RobotState& m, const dds_sample_info_t&) {
        if (m.mode == flsd_msgs_MODE_STAND && m.controller != nullptr) controller = m.controller;
      });
    }
    return out + "controller " + controller;
  });
  EXPECT_EQ(carol.out, "dds_create_topic(flsd/request): Not Allowed By Security; controller " + alice) << carol.err;
  EXPECT_TRUE(HasLine(ReadText(audit_path_), "Z identity " + alice + " [CN=alice,O=FLSD] (client_id " + alice +
                      ") request ", ": stand -> accepted (ok: standing)"));
  // The identity's first 12 digits are the fingerprint of the certificate's subject.
  const dds::CertificateSubject subject = dds::ReadCertificateSubject(pki_ + "/ours/alice/cert.pem");
  EXPECT_EQ(subject.fingerprint, alice.substr(0, 12));
  EXPECT_EQ(subject.name, "CN=alice,O=FLSD");
}

TEST_F(SkilldSecurityTest, FlsdClientUsesItsIdentityAndRefusesAnotherId) {
  const ChildResult bob = InChild([&] {
    Client::Options options;
    options.domain_id = domain_;
    options.partition = partition_;
    options.security = Identity("ours", "bob");
    Client client(options);
    if (!client.WaitForServer(20s)) return std::string("no server");
    std::string out = client.id() + " " + client.Call("acquire_control").Describe() + "; ";
    out += client.Call("status").message + "; ";
    options.client_id = "bob";
    try {
      Client named(options);
      out += "kept a declared id";
    } catch (const dds::Error& e) {
      out += e.what();
    }
    return out;
  });
  const std::string id = bob.out.substr(0, 25);
  EXPECT_THAT(id, ::testing::MatchesRegex("[0-9a-f]{12}-[0-9a-f]{12}"));
  EXPECT_THAT(bob.out, HasSubstr(" ok: control granted; "));
  EXPECT_THAT(bob.out, HasSubstr(", control " + id + ", "));
  EXPECT_THAT(bob.out, HasSubstr("client id 'bob' cannot be used with DDS Security: the server accepts only this "
                                 "participant's authenticated identity, "));
}

TEST_F(SkilldSecurityTest, AParticipantWithoutCredentialsNeitherReadsStateNorCommands) {
  ASSERT_THAT(AcquireAndStand("alice"), ::testing::MatchesRegex("[0-9a-f-]{25}")) << server_->Log();
  EXPECT_EQ(Reach({}, 3s), "shut out");
}

TEST_F(SkilldSecurityTest, AnotherCasOperatorIsShutOut) {
  ASSERT_THAT(AcquireAndStand("alice"), ::testing::MatchesRegex("[0-9a-f-]{25}")) << server_->Log();
  EXPECT_EQ(Reach(Identity("theirs", "mallory"), 3s), "shut out");  // valid in its own deployment
  EXPECT_THAT(ReadText(audit_path_), Not(HasSubstr("client_id " + std::string("mallory"))));
}

TEST_F(SkilldSecurityTest, AnExpiredCertificateIsRefused) {
  dds::SecurityConfig expired = Identity("ours", "alice");
  expired.identity_certificate = pki_ + "/expired/cert.pem";
  expired.private_key = pki_ + "/expired/key.pem";
  const ChildResult r = InChild([&] { return Connect(expired)->identity(); });
  EXPECT_THAT(r.out, HasSubstr("exception: dds_create_participant: DDS Security refused this participant's credentials"));
  EXPECT_THAT(r.err, HasSubstr("expired"));
}

TEST_F(SkilldSecurityTest, PermissionsAlteredAfterSigningAreRefused) {
  dds::SecurityConfig altered = Identity("ours", "carol");  // an observer who gives herself the request topic
  std::string text = ReadText(altered.permissions);
  const std::string grant = "<subscribe><topics>";
  ASSERT_NE(text.find(grant), std::string::npos);
  text.replace(text.find(grant), grant.size(), "<publish><topics><topic>flsd/request</topic></topics></publish>" + grant);
  const testutil::TempFile forged(".p7s", text);
  altered.permissions = forged.path();
  const ChildResult r = InChild([&] { return Connect(altered)->identity(); });
  EXPECT_THAT(r.out, HasSubstr("exception: dds_create_participant: DDS Security refused this participant's credentials"));
  EXPECT_THAT(r.err, HasSubstr("permissions"));
}

TEST_F(SkilldSecurityTest, AnOperatorSendingAnothersClientIdCannotTakeRenewOrUseTheirLease) {
  const std::string alice = AcquireAndStand("alice");
  ASSERT_THAT(alice, ::testing::MatchesRegex("[0-9a-f-]{25}")) << server_->Log();
  const ChildResult bob = InChild([&] {
    const std::unique_ptr<RawClient> raw = Connect(Identity("ours", "bob"));
    std::string out = raw->identity() + "\n";
    for (const char* call : {"acquire_control", "renew_control", "stand", "execute_skill", "stop", "release_control"}) {
      const RawReply r = Call(*raw, alice, call);
      out += std::string(call) + ": " + dds::StatusName(r.status) + ": " + r.message + "\n";
    }
    out += "own acquire_control: " + Call(*raw, raw->identity(), "acquire_control").message + "\n";
    const std::optional<RawState> s = raw->WaitForState([](const RawState&) { return true; }, 2s);
    return out + "controller " + (s ? s->controller : std::string("unknown"));
  });
  const std::string b = bob.out.substr(0, 25);
  ASSERT_NE(alice.substr(0, 12), b.substr(0, 12)) << "two certificates, two subject fingerprints";
  const std::string refusal = "invalid argument: client_id '" + alice + "' is not the authenticated identity of its " +
                              "writer (" + b + "); with DDS Security a client's id is its participant's identity; " +
                              "not executed\n";
  EXPECT_EQ(bob.out, b + "\nacquire_control: " + refusal + "renew_control: " + refusal + "stand: " + refusal +
                         "execute_skill: " + refusal + "stop: " + refusal + "release_control: " + refusal +
                         "own acquire_control: control is held by " + alice + "\ncontroller " + alice)
      << bob.err;
  const std::string audit = ReadText(audit_path_);
  const std::string impostor = "identity " + b + " [CN=bob,O=FLSD] (client_id " + alice + ") request ";
  EXPECT_TRUE(HasLine(audit, impostor, ": stop -> refused (invalid argument: client_id '" + alice +
                                           "' is not the authenticated identity of its writer (" + b + ")"));
  EXPECT_TRUE(HasLine(audit, impostor, ": execute_skill skill 1 duration 2.00 s -> refused (invalid argument: "));
  EXPECT_TRUE(HasLine(audit, "identity " + b + " [CN=bob,O=FLSD] (client_id " + b + ") request ",
                      ": acquire_control -> refused (not in control: control is held by " + alice + ")"));
}

// The adversarial suite's random requests, with security on: from the writer's own identity,
// someone else's, and names that are no identity.
TEST_F(SkilldSecurityTest, RandomRequestsAreAllAnsweredAndTheServerStillDamps) {
  const ChildResult fuzz = InChild([&] {
    const std::unique_ptr<RawClient> raw = Connect(Identity("ours", "alice"));
    const std::string id = raw->identity();
    fuzz::RandomRequests requests(20261202, {id, id, "0123456789ab-0123456789ab", "f0", std::string(70, 'c')});
    const int answered = testutil::Fuzz(*raw, requests, 3s, [&] { return server_->Log(); });
    const RawReply damp = Call(*raw, id, "damp");
    const bool damped = raw->WaitForState([](const RawState& s) { return s.mode == flsd_msgs_MODE_DAMP; }, 2s).has_value();
    return std::to_string(answered) + " answered, " + (::testing::Test::HasFailure() ? "with failures" : "all well") +
           "; damp: " + dds::StatusName(damp.status) + (damped ? ", damped" : ", not damped");
  });
  EXPECT_THAT(fuzz.out, ::testing::MatchesRegex("[0-9]{3,} answered, all well; damp: ok, damped")) << fuzz.err;
  server_->Signal(SIGTERM);
  EXPECT_EQ(server_->Wait(), 0) << server_->Log();
}

}  // namespace
}  // namespace flsd
