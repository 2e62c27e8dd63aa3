// The emergency stop never waits: while skilld reads the costliest map a client can send (the
// alias bomb an independent client sent, refused; the largest map accepted, planned), a damp
// from another client takes effect on the state topic within 50 ms, and a status call is answered
// as fast. Real skilld, real DDS on loopback, measured by the wall clock: its own label, run alone.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "navigation_map/map2d.h"
#include "tests/common/raw_dds_client.h"
#include "tests/common/skilld_fixture.h"

namespace flsd {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;
using fuzz::RawReply;
using fuzz::RawRequest;
using fuzz::RawState;

// A polygon of `n` points on a circle of radius 1 around (50, 50), far from the robot, as YAML.
std::string Circle(int n) {
  std::string polygon = "[";
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    char point[48];
    std::snprintf(point, sizeof point, "%s[%.3f, %.3f]", i ? ", " : "", 50 + std::cos(a), 50 + std::sin(a));
    polygon += point;
  }
  return polygon + "]";
}

// The map of the report: one 2000-point polygon and 2499 aliases of it (about 5 million points).
std::string AliasBomb() {
  std::string map = "bounds: [-100, 100, -100, 100]\npolygons:\n  - &p " + Circle(2000) + "\n";
  for (int i = 0; i < 2499; ++i) map += "  - *p\n";
  return map;
}

// The largest map accepted: 4096 points (2048 and one alias of them), padded with a comment to
// just under the size limit.
std::string HeaviestAcceptedMap() {
  std::string map = "bounds: [-100, 100, -100, 100]\npolygons:\n  - &p " + Circle(2048) + "\n  - *p\n";
  map += "#" + std::string(Map2D::kMaxTextBytes - map.size() - 2, 'x') + "\n";
  return map;
}

class SkilldTimingTest : public testutil::RawSkilldFixture {
 protected:
  // Sends navigate with `map`, and 20 ms later a status and a damp from two other clients:
  // returns the navigate's reply; expects the status answered and the damp in effect within 50 ms.
  RawReply NavigateThenDamp(const std::string& map) {
    RawRequest navigate = Request("holder", "navigate");
    navigate.goal = {1.0, 0.0};
    navigate.duration = 20.0;
    navigate.map_yaml = map;
    raw_->Send(navigate);
    std::this_thread::sleep_for(20ms);

    const RawRequest status = Request("observer", "status");
    auto sent = std::chrono::steady_clock::now();
    const std::optional<RawReply> status_reply = raw_->Call(status, 2s);
    EXPECT_TRUE(status_reply);
    EXPECT_LT(std::chrono::steady_clock::now() - sent, 50ms) << "status waited behind the map";

    const RawRequest damp = Request("bystander", "damp");
    sent = std::chrono::steady_clock::now();
    raw_->Send(damp);
    const std::optional<RawState> damped =
        raw_->WaitForState([](const RawState& s) { return s.mode == flsd_msgs_MODE_DAMP; }, 10s);
    EXPECT_TRUE(damped) << server_->Log();
    if (damped) {
      EXPECT_LT(damped->received - sent, 50ms) << "the emergency stop waited behind the map";
    }
    EXPECT_TRUE(raw_->Await(damp.client_id, damp.request_id, 2s));

    const std::optional<RawReply> reply = raw_->Await(navigate.client_id, navigate.request_id, 5s);
    EXPECT_TRUE(reply) << "navigate was not answered";
    return reply.value_or(RawReply{});
  }
};

TEST_F(SkilldTimingTest, TheEmergencyStopTakesEffectWithin50MsWhileAnAliasBombIsRead) {
  ASSERT_EQ(raw_->Call(Request("holder", "acquire_control"))->status, flsd_msgs_STATUS_OK);
  const RawReply reply = NavigateThenDamp(AliasBomb());
  EXPECT_EQ(reply.status, flsd_msgs_STATUS_INVALID_ARGUMENT);
  EXPECT_THAT(reply.message, HasSubstr("more than 4096 polygon points and circles"));
}

TEST_F(SkilldTimingTest, TheEmergencyStopTakesEffectWithin50MsWhileTheHeaviestAcceptedMapIsRead) {
  ASSERT_EQ(raw_->Call(Request("holder", "acquire_control"))->status, flsd_msgs_STATUS_OK);
  const std::string map = HeaviestAcceptedMap();
  ASSERT_EQ(Map2D::Parse(map, "heaviest").polygons.size(), 2u);
  const RawReply reply = NavigateThenDamp(map);
  // Accepted once read; the damp that came meanwhile ends its task (or keeps it from starting).
  EXPECT_EQ(reply.status, flsd_msgs_STATUS_OK) << reply.message;
  const std::optional<RawState> ended = raw_->WaitForState(
      [](const RawState& s) { return s.task_call == "navigate" && s.task_state != flsd_msgs_TASK_RUNNING; }, 5s);
  ASSERT_TRUE(ended);
  EXPECT_THAT(ended->task_message, ::testing::AnyOf(HasSubstr("emergency stop from bystander"),
                                                    HasSubstr("a safety stop latched before the task could start")));
  EXPECT_EQ(ended->mode, flsd_msgs_MODE_DAMP);
}

}  // namespace
}  // namespace flsd
