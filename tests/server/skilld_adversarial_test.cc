// An independent client against the real skilld over real DDS on loopback: requests written
// from idl/flsd_msgs.idl alone, with the ids, deadlines, maps and orderings a careless or hostile
// client sends. Each case asserts the reply and the mode on the state topic; the last one sends
// random well- and ill-typed requests for a few seconds and checks that every one was answered
// and that the server still stops the robot. (How soon the emergency stop acts is timed in
// skilld_timing_test.cc.)

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <climits>
#include <cmath>
#include <memory>

#include "tests/common/random_requests.h"
#include "tests/common/raw_dds_client.h"
#include "tests/common/skilld_fixture.h"

namespace flsd {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;
using fuzz::RawReply;
using fuzz::RawRequest;
using fuzz::RawState;

class SkilldAdversarialTest : public testutil::RawSkilldFixture {
 protected:
  RawReply Call(const RawRequest& r) {
    const std::optional<RawReply> reply = raw_->Call(r);
    EXPECT_TRUE(reply) << r.call << " from " << r.client_id << " was not answered";
    return reply.value_or(RawReply{});
  }
  RawReply Call(const std::string& client, const std::string& call) { return Call(Request(client, call)); }
  RawReply Skill(const std::string& client, int skill, double duration, uint64_t* id = nullptr) {
    RawRequest r = Request(client, "execute_skill");
    r.skill = skill;
    r.duration = duration;
    if (id != nullptr) *id = r.request_id;
    return Call(r);
  }
  std::optional<RawState> WaitForMode(flsd_msgs_Mode mode, std::chrono::milliseconds timeout) {
    return raw_->WaitForState([&](const RawState& s) { return s.mode == mode; }, timeout);
  }
};

TEST_F(SkilldAdversarialTest, AHolderCannotUndoABystandersEmergencyStop) {
  ASSERT_EQ(Call("holder", "acquire_control").status, flsd_msgs_STATUS_OK);
  ASSERT_EQ(Call("holder", "stand").status, flsd_msgs_STATUS_OK);
  ASSERT_TRUE(WaitForMode(flsd_msgs_MODE_STAND, 5s));
  ASSERT_EQ(Call("bystander", "damp").status, flsd_msgs_STATUS_OK);
  ASSERT_TRUE(WaitForMode(flsd_msgs_MODE_DAMP, 1s));
  // The holder's next stands, as a client standing the robot in a loop sends them.
  for (int i = 0; i < 3; ++i) {
    const RawReply stand = Call("holder", "stand");
    EXPECT_EQ(stand.status, flsd_msgs_STATUS_SAFETY_STOP);
    EXPECT_THAT(stand.message, HasSubstr("an emergency stop from bystander is latched; call clear_stop"));
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_FALSE(raw_->WaitForState([](const RawState& s) { return s.mode != flsd_msgs_MODE_DAMP; }, 300ms))
      << "the emergency stop was undone";
  const RawReply early = Call("holder", "clear_stop");
  EXPECT_EQ(early.status, flsd_msgs_STATUS_SAFETY_STOP);
  EXPECT_THAT(early.message, HasSubstr("bystander may at once, any client after"));
  EXPECT_EQ(Call("bystander", "clear_stop").status, flsd_msgs_STATUS_OK);
  ASSERT_TRUE(WaitForMode(flsd_msgs_MODE_IDLE, 1s)) << "clearing the stop should leave the robot damped and idle";
  EXPECT_EQ(Call("holder", "stand").status, flsd_msgs_STATUS_OK);
  EXPECT_TRUE(WaitForMode(flsd_msgs_MODE_STAND, 1s));
}

// X releases control, Y takes it and starts a skill, each answered at once: Y's task must go on.
TEST_F(SkilldAdversarialTest, AHandOverNeverEndsTheNewHoldersTask) {
  const std::string clients[] = {"x", "y"};
  ASSERT_EQ(Call("x", "acquire_control").status, flsd_msgs_STATUS_OK);
  for (int trial = 0; trial < 10; ++trial) {
    const std::string& from = clients[trial % 2];
    const std::string& to = clients[(trial + 1) % 2];
    ASSERT_EQ(Call(from, "release_control").status, flsd_msgs_STATUS_OK) << trial;
    ASSERT_EQ(Call(to, "acquire_control").status, flsd_msgs_STATUS_OK) << trial;
    uint64_t id = 0;
    ASSERT_EQ(Skill(to, 1, 3.0, &id).status, flsd_msgs_STATUS_OK) << trial;
    const std::optional<RawState> ended = raw_->WaitForState(
        [&](const RawState& s) {
          return s.task_request_id == id && s.task_state != flsd_msgs_TASK_RUNNING && s.task_state != flsd_msgs_TASK_NONE;
        },
        150ms);
    EXPECT_FALSE(ended) << "trial " << trial << ": " << to << "'s task ended "
                        << dds::TaskStateName(ended->task_state) << ": " << ended->task_message;
  }
}

TEST_F(SkilldAdversarialTest, AForgottenClientCannotReplayARequest) {
  RawRequest first = Request("e", "status");
  first.request_id = 777;
  ASSERT_EQ(Call(first).status, flsd_msgs_STATUS_OK);
  for (int i = 0; i < 300; ++i) ASSERT_EQ(Call("other-" + std::to_string(i), "status").status, flsd_msgs_STATUS_OK);
  const RawReply replay = Call(first);
  EXPECT_EQ(replay.status, flsd_msgs_STATUS_DUPLICATE) << replay.message;
  EXPECT_THAT(replay.message, HasSubstr("request_id 777 is not above"));
}

TEST_F(SkilldAdversarialTest, MapBoundsThePlannerCannotSampleAreRefusedNamingTheBound) {
  ASSERT_EQ(Call("holder", "acquire_control").status, flsd_msgs_STATUS_OK);
  for (const std::string bounds : {"[-.inf, .inf, -5, 5]", "[-1e300, 1e300, -5, 5]"}) {
    RawRequest r = Request("holder", "navigate");
    r.goal = {1.0, 0.0};
    r.map_yaml = "bounds: " + bounds + "\n";
    const RawReply reply = Call(r);
    EXPECT_EQ(reply.status, flsd_msgs_STATUS_INVALID_ARGUMENT) << bounds;
    EXPECT_THAT(reply.message, HasSubstr("bounds[0] (x_min): expected a finite number within [-1000, 1000] m")) << bounds;
  }
  // Nothing moved: the robot lies idle, with no task.
  const std::optional<RawState> s = raw_->WaitForState([](const RawState&) { return true; }, 1s);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->mode, flsd_msgs_MODE_IDLE);
  EXPECT_EQ(s->task_state, flsd_msgs_TASK_NONE);
}

TEST_F(SkilldAdversarialTest, AnImpossibleDeadlineIsRefusedByName) {
  RawRequest r = Request("c", "status");
  r.deadline_ns = INT64_MIN;
  const RawReply reply = Call(r);
  EXPECT_EQ(reply.status, flsd_msgs_STATUS_INVALID_ARGUMENT);
  EXPECT_THAT(reply.message, HasSubstr("deadline_ns must be 0 (none) or a CLOCK_REALTIME time in ns, got "
                                       "-9223372036854775808"));
  r = Request("c", "status");
  r.deadline_ns = dds_time() - 2'000'000'000;
  EXPECT_THAT(Call(r).message, ::testing::MatchesRegex("arrived 2\\.[0-9][0-9] s after its deadline; not executed"));
}

// As the README says: any request of the holder renews the lease; 1 s without one, it lapses.
TEST_F(SkilldAdversarialTest, AHolderThatOnlyAsksForStatusKeepsTheLease) {
  ASSERT_EQ(Call("holder", "acquire_control").status, flsd_msgs_STATUS_OK);
  const auto until = std::chrono::steady_clock::now() + 2500ms;
  while (std::chrono::steady_clock::now() < until) {
    ASSERT_EQ(Call("holder", "status").status, flsd_msgs_STATUS_OK);
    std::this_thread::sleep_for(250ms);
    const std::optional<RawState> s = raw_->WaitForState([](const RawState&) { return true; }, 1s);
    ASSERT_TRUE(s);
    ASSERT_EQ(s->controller, "holder") << "the lease lapsed while the holder kept calling status";
  }
  EXPECT_TRUE(raw_->WaitForState([](const RawState& s) { return s.controller.empty(); }, 2s));
}

// Random requests, well- and ill-typed, for three seconds: every one is answered with a status
// the IDL defines (a reason with every refusal), and afterwards the server answers and damps.
TEST_F(SkilldAdversarialTest, RandomRequestsAreAllAnsweredAndTheServerStillDamps) {
  fuzz::RandomRequests requests(20261202, {"f0", "f1", "f2", "f3", std::string(70, 'c')});
  EXPECT_GT(testutil::Fuzz(*raw_, requests, 3s, [&] { return server_->Log(); }), 100);

  EXPECT_EQ(Call("after", "status").status, flsd_msgs_STATUS_OK);
  ASSERT_EQ(Call("after", "damp").status, flsd_msgs_STATUS_OK);
  EXPECT_TRUE(WaitForMode(flsd_msgs_MODE_DAMP, 1s));
  server_->Signal(SIGTERM);
  EXPECT_EQ(server_->Wait(), 0) << server_->Log();
}

}  // namespace
}  // namespace flsd
