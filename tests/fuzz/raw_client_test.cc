// The raw client's matching of replies on loopback DDS, with replies written as skilld would: a
// request given up on may still be answered, after the soak repeated its ids in a new request.

#include "fuzz/raw_client.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "tests/common/dds_support.h"

namespace flsd::fuzz {
namespace {

using namespace std::chrono_literals;

class RawClientTest : public ::testing::Test {
 protected:
  void SetUp() override { testutil::UseLoopbackDds(); }
};

// skilld's side: replies from a participant of its own.
class Replier {
 public:
  Replier() : writer_(domain_, flsd_msgs_Reply_desc, dds::kReplyTopic, dds::kReplyQos) {
    for (int i = 0; i < 500 && writer_.matched_readers() == 0; ++i) std::this_thread::sleep_for(10ms);
  }
  int matched() const { return writer_.matched_readers(); }
  void Answer(const std::string& client_id, uint64_t request_id, flsd_msgs_ReplyStatus status) const {
    flsd_msgs_Reply m{};
    m.header.client_id = const_cast<char*>(client_id.c_str());
    m.header.request_id = request_id;
    m.status = status;
    m.message = m.safety_report = const_cast<char*>("");
    writer_.Write(m);
  }

 private:
  dds::Domain domain_{testutil::TestDomainId(), testutil::TestPartition()};
  dds::Writer<flsd_msgs_Reply> writer_;
};

RawRequest Stand(uint64_t id) {
  RawRequest r;
  r.client_id = "alice";
  r.request_id = id;
  r.call = "stand";
  return r;
}

bool IsDuplicate(const RawReply& reply) { return reply.status == flsd_msgs_STATUS_DUPLICATE; }

TEST_F(RawClientTest, ALateReplyBeforeTheRepeatsOwnIsCountedLate) {
  RawClient raw(testutil::TestDomainId(), testutil::TestPartition());
  const Replier skilld;
  ASSERT_EQ(skilld.matched(), 1);
  raw.Send(Stand(5));
  EXPECT_FALSE(raw.Await("alice", 5, 100ms));
  raw.Send(Stand(5));  // the same ids again: skilld answers it duplicate
  skilld.Answer("alice", 5, flsd_msgs_STATUS_OK);  // the first, late
  skilld.Answer("alice", 5, flsd_msgs_STATUS_DUPLICATE);
  const std::optional<RawReply> reply = raw.Await("alice", 5, 5000ms, IsDuplicate);
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->status, flsd_msgs_STATUS_DUPLICATE);
  EXPECT_EQ(raw.late_replies(), 1);
}

TEST_F(RawClientTest, ALateReplyAfterTheRepeatsOwnIsCountedLate) {
  RawClient raw(testutil::TestDomainId(), testutil::TestPartition());
  const Replier skilld;
  ASSERT_EQ(skilld.matched(), 1);
  raw.Send(Stand(5));
  EXPECT_FALSE(raw.Await("alice", 5, 100ms));
  raw.Send(Stand(5));
  skilld.Answer("alice", 5, flsd_msgs_STATUS_DUPLICATE);
  const std::optional<RawReply> reply = raw.Await("alice", 5, 5000ms, IsDuplicate);
  ASSERT_TRUE(reply);
  EXPECT_EQ(reply->status, flsd_msgs_STATUS_DUPLICATE);
  skilld.Answer("alice", 5, flsd_msgs_STATUS_OK);  // the first, later still
  for (int i = 0; i < 500 && raw.late_replies() == 0; ++i) std::this_thread::sleep_for(10ms);
  EXPECT_EQ(raw.late_replies(), 1);
  // Nothing more is owed: a further reply with those ids is no late one.
  skilld.Answer("alice", 5, flsd_msgs_STATUS_OK);
  std::this_thread::sleep_for(200ms);
  EXPECT_EQ(raw.late_replies(), 1);
}

}  // namespace
}  // namespace flsd::fuzz
