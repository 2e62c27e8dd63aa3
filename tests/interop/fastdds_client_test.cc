// Another vendor's client of the real skilld: eProsima's fastddsgen compiles idl/flsd_msgs.idl as
// it is, and a Fast DDS participant of those types reads the state topic and makes calls over the
// request and reply topics, as the README's client contract says, against Cyclone DDS on loopback.

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

#include "api/calls.h"
#include "api/modes.h"
#include "flsd_msgsPubSubTypes.h"
#include "tests/common/skilld_fixture.h"

namespace flsd {
namespace {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;
using namespace std::chrono_literals;
using ::testing::HasSubstr;
using ::testing::StartsWith;

eprosima::fastrtps::Duration_t FastDdsDuration(std::chrono::steady_clock::duration d) {
  return eprosima::fastrtps::Duration_t(std::chrono::duration<long double>(d).count());
}

// Beside Cyclone on loopback (configs/cyclonedds_loopback.xml): UDPv4 on 127.0.0.1 alone. Fast DDS's
// built-in transports announce every interface's address, and Cyclone, held to 127.0.0.1, then
// never answers. Discovery starts by unicast to 127.0.0.1's well-known ports, as Cyclone's peer
// list does (port 0: those of the first participant indices), rather than by multicast alone.
fdds::DomainParticipantQos LoopbackParticipantQos() {
  fdds::DomainParticipantQos qos;
  qos.transport().use_builtin_transports = false;
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.push_back("127.0.0.1");
  qos.transport().user_transports.push_back(udp);
  eprosima::fastrtps::rtps::Locator_t peer;
  eprosima::fastrtps::rtps::IPLocator::setIPv4(peer, "127.0.0.1");
  qos.wire_protocol().builtin.initialPeersList.push_back(peer);
  return qos;
}

// Fast DDS answers a failed creation with a null entity.
template <class Entity>
Entity* Created(Entity* entity, const char* what) {
  if (entity == nullptr) throw std::runtime_error(std::string("Fast DDS could not create ") + what);
  return entity;
}

// The README's QoS: requests and replies reliable, keep-last 64; state best effort, keep-last 1;
// all volatile.
template <class Qos>
Qos EndpointQos(Qos qos, bool reliable, int depth) {
  qos.reliability().kind = reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = depth;
  qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
  return qos;
}

class FastDdsClient {
 public:
  FastDdsClient(int domain_id, const std::string& partition)
      : participant_(Created(fdds::DomainParticipantFactory::get_instance()->create_participant(
                                     domain_id, LoopbackParticipantQos()),
                             "the participant")) {
    fdds::PublisherQos publisher_qos;
    publisher_qos.partition().push_back(partition.c_str());
    fdds::SubscriberQos subscriber_qos;
    subscriber_qos.partition().push_back(partition.c_str());
    fdds::Publisher* publisher = Created(participant_->create_publisher(publisher_qos), "the publisher");
    fdds::Subscriber* subscriber = Created(participant_->create_subscriber(subscriber_qos), "the subscriber");
    requests_ = Created(publisher->create_datawriter(Topic("flsd/request", request_type_),
                                                     EndpointQos(fdds::DATAWRITER_QOS_DEFAULT, true, 64)),
                        "the request writer");
    replies_ = Created(subscriber->create_datareader(Topic("flsd/reply", reply_type_),
                                                     EndpointQos(fdds::DATAREADER_QOS_DEFAULT, true, 64)),
                       "the reply reader");
    states_ = Created(subscriber->create_datareader(Topic("flsd/state", state_type_),
                                                    EndpointQos(fdds::DATAREADER_QOS_DEFAULT, false, 1)),
                      "the state reader");
  }
  ~FastDdsClient() {
    participant_->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
  FastDdsClient(const FastDdsClient&) = delete;
  FastDdsClient& operator=(const FastDdsClient&) = delete;

  // Sends `call` with the next request id; its reply, or nullopt after `timeout`.
  std::optional<flsd_msgs::Reply> Call(const std::string& call, std::chrono::milliseconds timeout = 2s) {
    flsd_msgs::Request request;
    request.header().client_id(kClientId);
    request.header().request_id(++request_id_);
    request.call(call);
    requests_->write(&request);
    const auto until = std::chrono::steady_clock::now() + timeout;
    flsd_msgs::Reply reply;
    fdds::SampleInfo info;
    for (;;) {
      while (replies_->take_next_sample(&reply, &info) == ReturnCode_t::RETCODE_OK) {
        if (info.valid_data && reply.header().client_id() == kClientId && reply.header().request_id() == request_id_) {
          return reply;
        }
      }
      const auto now = std::chrono::steady_clock::now();
      if (now >= until) return std::nullopt;
      replies_->wait_for_unread_message(FastDdsDuration(until - now));
    }
  }

  // Until skilld answers a status call: a request sent before the endpoints match is lost.
  bool WaitForServer(std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < until) {
      if (Call("status", 200ms)) return true;
    }
    return false;
  }

  // The next state sample, or nullopt after `timeout`.
  std::optional<flsd_msgs::RobotState> NextState(std::chrono::milliseconds timeout) {
    flsd_msgs::RobotState state;
    fdds::SampleInfo info;
    const auto until = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      while (states_->take_next_sample(&state, &info) == ReturnCode_t::RETCODE_OK) {
        if (info.valid_data) return state;
      }
      const auto now = std::chrono::steady_clock::now();
      if (now >= until) return std::nullopt;
      states_->wait_for_unread_message(FastDdsDuration(until - now));
    }
  }

 private:
  static constexpr const char* kClientId = "fastdds-client";

  fdds::Topic* Topic(const char* name, fdds::TypeSupport& type) {
    type.register_type(participant_);
    return participant_->create_topic(name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
  }

  fdds::DomainParticipant* participant_;
  fdds::TypeSupport request_type_{new flsd_msgs::RequestPubSubType()};
  fdds::TypeSupport reply_type_{new flsd_msgs::ReplyPubSubType()};
  fdds::TypeSupport state_type_{new flsd_msgs::RobotStatePubSubType()};
  fdds::DataWriter* requests_ = nullptr;
  fdds::DataReader* replies_ = nullptr;
  fdds::DataReader* states_ = nullptr;
  // From the wall clock, as the contract asks: ids grow across the server's life.
  uint64_t request_id_ = static_cast<uint64_t>(std::chrono::system_clock::now().time_since_epoch().count());
};

class FastDdsClientTest : public testutil::SkilldFixture {
 protected:
  void SetUp() override {
    SkilldFixture::SetUp();
    StartServer();
    client_ = std::make_unique<FastDdsClient>(domain_, partition_);
    ASSERT_TRUE(client_->WaitForServer(15s)) << "no reply from skilld to a Fast DDS client\n" << server_->Log();
  }

  std::unique_ptr<FastDdsClient> client_;
};

TEST_F(FastDdsClientTest, TheStateArrivesAtTheControlRateWithSaneContents) {
  const std::optional<flsd_msgs::RobotState> first = client_->NextState(5s);
  ASSERT_TRUE(first) << "no state sample reached the Fast DDS client";
  const auto start = std::chrono::steady_clock::now();
  std::vector<flsd_msgs::RobotState> states;
  while (std::chrono::steady_clock::now() - start < 2s) {
    std::optional<flsd_msgs::RobotState> s = client_->NextState(1s);
    ASSERT_TRUE(s) << "the state stopped after " << states.size() << " samples";
    states.push_back(std::move(*s));
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NEAR(states.size() / seconds, 50.0, 10.0);
  const flsd_msgs::RobotState* previous = &*first;
  for (const flsd_msgs::RobotState& s : states) {
    ASSERT_GT(s.tick(), previous->tick());
    EXPECT_NEAR(s.time() - previous->time(), (s.tick() - previous->tick()) * 0.02, 1e-9) << "tick " << s.tick();
    previous = &s;
  }
  // Nothing was asked of the robot: it lies idle on the simulated backend, with no task.
  const flsd_msgs::RobotState& last = states.back();
  EXPECT_EQ(last.backend(), "sim");
  EXPECT_STREQ(Name(static_cast<Mode>(last.mode())), "idle");
  EXPECT_EQ(last.task().state(), flsd_msgs::TASK_NONE);
  EXPECT_EQ(last.controller(), "");
  EXPECT_EQ(last.faults(), 0u);
  const std::array<double, 4>& q = last.orientation();
  EXPECT_NEAR(std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]), 1.0, 1e-6);
  EXPECT_GT(last.position()[2], 0.0);
}

// The skills as skillctl, a Cyclone client, lists them: one row per skill, its id and vx.
TEST_F(FastDdsClientTest, ListSkillsAgreesWithSkillctl) {
  const std::optional<flsd_msgs::Reply> reply = client_->Call("list_skills");
  ASSERT_TRUE(reply);
  ASSERT_EQ(reply->status(), flsd_msgs::STATUS_OK) << reply->message();
  const std::vector<flsd_msgs::SkillInfo>& skills = reply->skills();
  EXPECT_EQ(reply->message(), std::to_string(skills.size()) + " skills");

  const auto [code, out] = Skillctl({"list"});
  ASSERT_EQ(code, 0) << out;
  std::istringstream lines(out);
  std::string line;
  std::getline(lines, line);  // the header
  ASSERT_THAT(line, StartsWith("skill"));
  size_t rows = 0;
  while (std::getline(lines, line)) {
    int id = -1;
    double vx = NAN;
    ASSERT_EQ(std::sscanf(line.c_str(), "%d %lf", &id, &vx), 2) << line;
    ASSERT_LT(rows, skills.size()) << "skillctl lists more skills than the Fast DDS reply: " << line;
    EXPECT_EQ(skills[rows].id(), id);
    EXPECT_NEAR(skills[rows].linear_velocity()[0], vx, 0.005) << line;
    ++rows;
  }
  EXPECT_EQ(rows, skills.size());
  EXPECT_GT(rows, 0u);
}

TEST_F(FastDdsClientTest, StatusAndAnUnknownCallGetTheirDocumentedReplies) {
  const std::optional<flsd_msgs::Reply> status = client_->Call("status");
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status(), flsd_msgs::STATUS_OK);
  EXPECT_THAT(status->message(), StartsWith("mode idle, t "));
  EXPECT_THAT(status->message(), HasSubstr("control free, faults none"));

  const std::optional<flsd_msgs::Reply> unknown = client_->Call("fly");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status(), flsd_msgs::STATUS_UNKNOWN_CALL);
  EXPECT_EQ(unknown->message(), "unknown call 'fly'; known calls: " + KnownCalls());
  EXPECT_TRUE(unknown->skills().empty());
}

}  // namespace
}  // namespace flsd
