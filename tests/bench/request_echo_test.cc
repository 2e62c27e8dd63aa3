// skillctl bench's echo on loopback DDS: a flsd Client's calls come back answered ok, matched to
// their own request ids, whatever their name, and only in the echo's partition.

#include "bench/request_echo.h"

#include <gtest/gtest.h>

#include <chrono>

#include "client/client.h"
#include "tests/common/dds_support.h"

namespace flsd {
namespace {

using namespace std::chrono_literals;

Client::Options In(const std::string& partition) {
  Client::Options options;
  options.domain_id = testutil::TestDomainId();
  options.partition = partition;
  return options;
}

TEST(RequestEchoTest, AnswersEveryCallOkWithItsOwnRequestId) {
  testutil::UseLoopbackDds();
  const std::string partition = EchoPartition(testutil::TestPartition());
  const RequestEcho echo(testutil::TestDomainId(), partition);
  Client client(In(partition));
  ASSERT_TRUE(client.WaitForServer(10s));
  for (const char* call : {"status", "status", "no_such_call"}) {
    const CallResult r = client.Call(call, {}, 1000ms);
    EXPECT_TRUE(r.ok()) << call;
    EXPECT_EQ(r.message, "") << call;
  }
  // Request ids rise call by call; each answer was matched to its own.
  const CallResult first = client.Call("status", {}, 1000ms);
  const CallResult second = client.Call("status", {}, 1000ms);
  EXPECT_TRUE(first.ok());
  EXPECT_TRUE(second.ok());
  EXPECT_EQ(second.request_id, first.request_id + 1);
}

TEST(RequestEchoTest, IsNotReachedFromTheServersPartition) {
  testutil::UseLoopbackDds();
  const std::string partition = testutil::TestPartition();
  const RequestEcho echo(testutil::TestDomainId(), EchoPartition(partition));
  Client beside(In(EchoPartition(partition)));
  ASSERT_TRUE(beside.WaitForServer(10s));  // discovery is done: the echo answers in its own partition
  Client client(In(partition));
  EXPECT_FALSE(client.WaitForServer(1000ms));
}

}  // namespace
}  // namespace flsd
