// The RAII layer over Cyclone on loopback: a sample survives the round trip with its strings and
// sequences, partitions separate traffic, and waits time out or wake on a guard.

#include "comm/dds.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "comm/protocol.h"
#include "tests/common/dds_support.h"

namespace flsd::dds {
namespace {

using namespace std::chrono_literals;

class DdsTest : public ::testing::Test {
 protected:
  void SetUp() override { testutil::UseLoopbackDds(); }
};

template <class R, class W>
void WaitForMatch(const R& reader, const W& writer) {
  for (int i = 0; i < 500 && (reader.matched_writers() == 0 || writer.matched_readers() == 0); ++i) {
    std::this_thread::sleep_for(10ms);
  }
}

TEST_F(DdsTest, ARequestCrossesBetweenParticipantsIntact) {
  Domain a(testutil::TestDomainId(), testutil::TestPartition());
  Domain b(testutil::TestDomainId(), testutil::TestPartition());
  Writer<flsd_msgs_Request> writer(a, flsd_msgs_Request_desc, kRequestTopic, kRequestQos);
  Reader<flsd_msgs_Request> reader(b, flsd_msgs_Request_desc, kRequestTopic, kRequestQos);
  WaitForMatch(reader, writer);
  ASSERT_EQ(reader.matched_writers(), 1);

  std::string client = "client-1", call = "execute_skill", map = "obstacles: []";
  flsd_msgs_Request sent{};
  sent.header.client_id = client.data();
  sent.header.request_id = 1234567890123ull;
  sent.header.deadline_ns = -5;
  sent.call = call.data();
  sent.skill = 7;
  sent.duration = 2.5;
  sent.velocity[2] = -0.75;
  sent.goal[1] = 3.25;
  sent.map_yaml = map.data();
  writer.Write(sent);

  ASSERT_TRUE(reader.Wait(5s));
  int received = 0;
  reader.Take([&](const flsd_msgs_Request& r, const dds_sample_info_t&) {
    ++received;
    EXPECT_STREQ(r.header.client_id, "client-1");
    EXPECT_EQ(r.header.request_id, 1234567890123ull);
    EXPECT_EQ(r.header.deadline_ns, -5);
    EXPECT_STREQ(r.call, "execute_skill");
    EXPECT_EQ(r.skill, 7);
    EXPECT_EQ(r.duration, 2.5);
    EXPECT_EQ(r.velocity[2], -0.75);
    EXPECT_EQ(r.goal[1], 3.25);
    EXPECT_STREQ(r.map_yaml, "obstacles: []");
  });
  EXPECT_EQ(received, 1);
}

TEST_F(DdsTest, ASequenceOfSkillsCrossesIntact) {
  Domain a(testutil::TestDomainId(), testutil::TestPartition());
  Writer<flsd_msgs_Reply> writer(a, flsd_msgs_Reply_desc, kReplyTopic, kReplyQos);
  Reader<flsd_msgs_Reply> reader(a, flsd_msgs_Reply_desc, kReplyTopic, kReplyQos);
  WaitForMatch(reader, writer);
  std::vector<flsd_msgs_SkillInfo> skills(3);
  for (int k = 0; k < 3; ++k) {
    skills[k].id = k;
    skills[k].linear_velocity[0] = 0.1 * k;
  }
  flsd_msgs_Reply sent{};
  sent.header.client_id = const_cast<char*>("c");
  sent.message = sent.safety_report = const_cast<char*>("");
  sent.status = flsd_msgs_STATUS_NOT_IN_CONTROL;
  sent.skills._buffer = skills.data();
  sent.skills._length = sent.skills._maximum = 3;
  writer.Write(sent);
  ASSERT_TRUE(reader.Wait(5s));
  reader.Take([&](const flsd_msgs_Reply& r, const dds_sample_info_t&) {
    EXPECT_EQ(r.status, flsd_msgs_STATUS_NOT_IN_CONTROL);
    ASSERT_EQ(r.skills._length, 3u);
    EXPECT_EQ(r.skills._buffer[2].id, 2);
    EXPECT_DOUBLE_EQ(r.skills._buffer[2].linear_velocity[0], 0.2);
  });
}

TEST_F(DdsTest, PartitionsKeepServersApart) {
  Domain a(testutil::TestDomainId(), testutil::TestPartition() + "-robot1");
  Domain b(testutil::TestDomainId(), testutil::TestPartition() + "-robot2");
  Writer<flsd_msgs_Request> writer(a, flsd_msgs_Request_desc, kRequestTopic, kRequestQos);
  Reader<flsd_msgs_Request> reader(b, flsd_msgs_Request_desc, kRequestTopic, kRequestQos);
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(reader.matched_writers(), 0);
  flsd_msgs_Request r{};
  r.header.client_id = r.call = r.map_yaml = const_cast<char*>("");
  writer.Write(r);
  EXPECT_FALSE(reader.Wait(200ms));
}

TEST_F(DdsTest, WaitTimesOutWithoutDataAndWakesOnTheGuard) {
  Domain a(testutil::TestDomainId(), testutil::TestPartition());
  Reader<flsd_msgs_Request> reader(a, flsd_msgs_Request_desc, kRequestTopic, kRequestQos);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(reader.Wait(100ms));
  EXPECT_GE(std::chrono::steady_clock::now() - start, 90ms);

  Guard guard(a);
  std::thread waker([&] {
    std::this_thread::sleep_for(50ms);
    guard.Trigger();
  });
  const auto woken = std::chrono::steady_clock::now();
  EXPECT_FALSE(reader.Wait(10s, guard.get()));  // woken, but no data
  EXPECT_LT(std::chrono::steady_clock::now() - woken, 5s);
  waker.join();
}

TEST_F(DdsTest, ErrorsNameTheCallThatFailed) {
  EXPECT_THROW(Domain(233, ""), Error);
  try {
    Check(DDS_RETCODE_BAD_PARAMETER, "dds_frobnicate");
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "dds_frobnicate: Bad Parameter");
  }
}

}  // namespace
}  // namespace flsd::dds
