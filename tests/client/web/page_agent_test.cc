// skillweb's side of a page agent, against scripts that speak its protocol badly: one that stalls
// within its first line, one whose replies have the wrong shape, one that answers late and one
// that stops reading.

#include "client/web/page_agent.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>

#include "tests/common/test_support.h"

namespace flsd::web {
namespace {

using Clock = std::chrono::steady_clock;

// An agent that runs `script` (sh), removed with it.
class FakeAgent {
 public:
  explicit FakeAgent(const std::string& script) : path_(testutil::UniqueTempPath("agent.sh")) {
    std::ofstream(path_) << "#!/bin/sh\n" << script;
    chmod(path_.c_str(), 0700);
  }
  ~FakeAgent() { std::remove(path_.c_str()); }
  AgentOptions Options() const {
    AgentOptions options;
    options.program = path_;
    options.start_timeout = std::chrono::milliseconds(300);
    options.reply_timeout = std::chrono::milliseconds(300);
    return options;
  }

 private:
  std::string path_;
};

TEST(AgentPageLinkTest, AnAgentThatStallsWithinItsFirstLineDoesNotStart) {
  const FakeAgent agent("printf 'I half a line'\nexec sleep 30\n");
  const auto started = Clock::now();
  try {
    AgentPageLink link(agent.Options());
    ADD_FAILURE() << "an agent that never finished its first line started";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "its DDS client did not start");
  }
  // The timeout, then up to 3 s for the agent to go before it is killed.
  EXPECT_LT(Clock::now() - started, std::chrono::seconds(10));
}

TEST(AgentPageLinkTest, RepliesOfTheWrongShapeAreRefusedWithTheReason) {
  const FakeAgent agent(
      "echo 'I fake-agent'\n"
      "read request; echo 'R {\"id\": 1, \"status\": 200}'\n"
      "read request; echo 'R {\"id\": 2, \"status\": 200, \"reply\": {\"ok\": true}}'\n"
      "read request; echo 'R {\"id\": 3, \"status\": 200, \"reply\": []}'\n"
      "exec cat > /dev/null\n");
  AgentPageLink link(agent.Options());
  EXPECT_EQ(link.id(), "fake-agent");
  int status = 0;
  const nlohmann::json no_reply = link.Command("stand", "", status);
  EXPECT_EQ(status, 502);
  EXPECT_EQ(no_reply["message"], "this page's DDS client answered out of protocol: no reply object or list");
  const nlohmann::json no_audit = link.Command("stand", "", status);
  EXPECT_EQ(status, 502);
  EXPECT_EQ(no_audit["message"], "this page's DDS client answered out of protocol: a command's reply without its audit");
  EXPECT_EQ(link.Skills(status), nlohmann::json::array());
  EXPECT_EQ(status, 200);
}

TEST(AgentPageLinkTest, AnAnswerAfterItsRequestGaveUpIsDropped) {
  const FakeAgent agent(
      "echo 'I fake-agent'\n"
      "read first; read second\n"
      "echo 'R {\"id\": 1, \"status\": 200, \"reply\": {\"ok\": true, \"audit\": \"late\"}}'\n"
      "echo 'R {\"id\": 2, \"status\": 200, \"reply\": {\"ok\": true, \"audit\": \"second\"}}'\n"
      "exec cat > /dev/null\n");
  AgentPageLink link(agent.Options());
  testing::internal::CaptureStderr();
  int status = 0;
  const nlohmann::json first = link.Command("stand", "", status);
  EXPECT_EQ(status, 503);
  EXPECT_EQ(first["message"], "no answer from this page's DDS client");
  // The late answer to the first comes before the second's: it has been read, and dropped, by then.
  const nlohmann::json second = link.Command("stop", "", status);
  const std::string log = testing::internal::GetCapturedStderr();
  EXPECT_EQ(status, 200);
  EXPECT_EQ(second["audit"], "second");
  EXPECT_NE(log.find("page agent fake-agent: dropped the late answer to request 1"), std::string::npos) << log;
}

TEST(AgentPageLinkTest, AnAgentThatStopsReadingIsEndedInsteadOfHoldingTheWriter) {
  const FakeAgent agent("echo 'I fake-agent'\nexec sleep 30\n");
  AgentPageLink link(agent.Options());
  int status = 0;
  const auto sent = Clock::now();
  // More than a pipe holds (64 KiB): the write waits for a reader that never comes.
  const nlohmann::json reply = link.Command("stand", std::string(1 << 20, 'x'), status);
  EXPECT_LT(Clock::now() - sent, std::chrono::seconds(3));
  EXPECT_EQ(status, 503);
  EXPECT_EQ(reply["message"], "this page's DDS client has exited or stopped taking requests");
  for (int i = 0; i < 100 && link.alive(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_FALSE(link.alive());  // the page's streams end
  EXPECT_EQ(link.Command("stand", "", status)["message"], "this page's DDS client has exited or stopped taking requests");
}

}  // namespace
}  // namespace flsd::web
