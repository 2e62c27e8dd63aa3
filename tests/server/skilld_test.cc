// The real skilld process over real DDS on loopback, driven by flsd::Client: a skill runs end to
// end, control is exclusive and lapses, bad and flooding requests are answered or counted while
// the server keeps running, and SIGTERM stops it cleanly with the robot damped.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <fstream>
#include <iterator>

#include "comm/protocol.h"
#include "skills/runtime/hierarchical_policy.h"
#include "skills/runtime/skill_library.h"
#include "tests/common/client_skilld_fixture.h"
#include "tests/common/test_support.h"

namespace flsd {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

class SkilldTest : public testutil::ClientSkilldFixture {
 protected:  static bool Standing(const StateSample& s) {
    return s.msg.mode == flsd_msgs_MODE_STAND && s.msg.position[2] > 0.22;
  }
};

TEST_F(SkilldTest, AClientListsSkillsStandsAndRunsASkillToItsEnd) {
  StartServer();
  auto client = Connect();
  const SkillLibrary library = SkillLibrary::Load(FLSD_SOURCE_DIR "/models/a1_flsd.safetensors");
  const CallResult list = client->Call("list_skills");
  ASSERT_TRUE(list.ok()) << list.Describe();
  ASSERT_EQ(static_cast<int>(list.skills.size()), library.num_skills());
  EXPECT_EQ(list.skills[1].survival_steps, library.skills()[1].survival_steps);

  ASSERT_TRUE(client->AcquireControl().ok());
  ASSERT_TRUE(client->Call("stand").ok());
  ASSERT_TRUE(client->WaitForState(Standing, 10s)) << "the robot did not stand";

  CallArgs args;
  args.skill = 0;
  args.duration = 2.0;
  const CallResult r = client->Call("execute_skill", args);
  ASSERT_TRUE(r.ok()) << r.Describe();
  const auto running = client->WaitForState(
      [](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_SKILL && s.msg.skill == 0; }, 5s);
  ASSERT_TRUE(running) << "the skill did not start";
  EXPECT_EQ(running->task_call, "execute_skill");
  EXPECT_EQ(running->task_client_id, client->id());
  EXPECT_EQ(running->controller, client->id());

  const auto done = client->WaitForState(
      [](const StateSample& s) { return s.msg.task.state != flsd_msgs_TASK_RUNNING && s.task_call == "execute_skill"; },
      10s);
  ASSERT_TRUE(done);
  EXPECT_EQ(done->msg.task.state, flsd_msgs_TASK_SUCCEEDED) << done->task_message;
  EXPECT_EQ(done->msg.mode, flsd_msgs_MODE_STAND);
  EXPECT_EQ(done->msg.faults, 0u);
  EXPECT_EQ(done->backend, "sim");
}

// track_velocity: the selector chooses skills each tick for the command (clipped to its trained
// range, which the reply reports), and the task ends when its duration is up.
TEST_F(SkilldTest, TracksAVelocityCommandWithTheSelector) {
  StartServer();
  auto client = Connect();
  ASSERT_TRUE(client->AcquireControl().ok());
  CallArgs args;
  args.velocity = {5.0, 0.0, 0.0};
  args.duration = 3.0;
  const CallResult r = client->Call("track_velocity", args);
  ASSERT_TRUE(r.ok()) << r.Describe();
  const SkillLibrary library = SkillLibrary::Load(FLSD_SOURCE_DIR "/models/a1_flsd.safetensors");
  const HierarchicalPolicy served(library, library.selector() ? SelectorKind::kLearned : SelectorKind::kTimeSharing);
  EXPECT_THAT(r.message, HasSubstr(testutil::ClippedTo("vx", served.CommandRange()[1][0])));
  const auto walking = client->WaitForState(
      [](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_VELOCITY && s.msg.skill >= 0; }, 10s);
  ASSERT_TRUE(walking) << "the velocity task did not start";
  EXPECT_EQ(walking->task_call, "track_velocity");
  const auto done = client->WaitForState(
      [](const StateSample& s) { return s.msg.task.state != flsd_msgs_TASK_RUNNING && s.task_call == "track_velocity"; },
      10s);
  ASSERT_TRUE(done);
  EXPECT_EQ(done->msg.task.state, flsd_msgs_TASK_SUCCEEDED) << done->task_message;
  EXPECT_EQ(done->msg.mode, flsd_msgs_MODE_STAND);
  EXPECT_EQ(done->msg.faults, 0u) << done->fault_message;
}

// navigate, each outcome on a map with a known answer: a goal inside an obstacle and an enclosed
// goal have no path; a goal within the tolerance is reached; a walk is followed along a published
// path until it is cancelled.
TEST_F(SkilldTest, NavigationEndsAsNoPathReachedOrCancelledWithTheReason) {
  StartServer();
  auto client = Connect();
  ASSERT_TRUE(client->AcquireControl().ok());
  auto navigate = [&](double x, double y, const std::string& map_yaml) {
    CallArgs args;
    args.goal = {x, y};
    args.map_yaml = map_yaml;
    const CallResult r = client->Call("navigate", args);
    EXPECT_TRUE(r.ok()) << r.Describe();
    return client->WaitForState(
        [&](const StateSample& s) { return s.msg.task.request_id == r.request_id && s.msg.task.state != flsd_msgs_TASK_RUNNING; },
        15s);
  };
  const std::string open = "bounds: [-5, 5, -5, 5]\nrobot_radius: 0.35\n";
  const auto inside = navigate(2.0, 0.0, open + "circles: [{center: [2.0, 0.0], radius: 0.5}]\n");
  ASSERT_TRUE(inside);
  EXPECT_EQ(inside->msg.task.state, flsd_msgs_TASK_NO_PATH);
  EXPECT_THAT(inside->task_message, HasSubstr("goal"));

  std::ifstream enclosed_file(FLSD_SOURCE_DIR "/configs/maps/enclosed.yaml");
  const std::string enclosed((std::istreambuf_iterator<char>(enclosed_file)), std::istreambuf_iterator<char>());
  const auto unreachable = navigate(3.0, 3.0, enclosed);
  ASSERT_TRUE(unreachable);
  EXPECT_EQ(unreachable->msg.task.state, flsd_msgs_TASK_NO_PATH);

  const auto here = navigate(0.1, 0.05, open);
  ASSERT_TRUE(here);
  EXPECT_EQ(here->msg.task.state, flsd_msgs_TASK_SUCCEEDED) << here->task_message;
  EXPECT_THAT(here->task_message, HasSubstr("reached"));

  CallArgs far;
  far.goal = {4.0, 0.0};
  far.map_yaml = open;
  const CallResult walk = client->Call("navigate", far);
  ASSERT_TRUE(walk.ok()) << walk.Describe();
  const auto following = client->WaitForState(
      [&](const StateSample& s) {
        return s.msg.task.request_id == walk.request_id && s.msg.mode == flsd_msgs_MODE_NAVIGATE && s.task_path.size() >= 4;
      },
      10s);
  ASSERT_TRUE(following) << "no path was published while navigating";
  EXPECT_NEAR(following->task_path[following->task_path.size() - 2], 4.0, 1e-9);
  EXPECT_NEAR(following->task_path.back(), 0.0, 1e-9);
  ASSERT_TRUE(client->Call("stop").ok());
  const auto stopped = client->WaitForState(
      [&](const StateSample& s) { return s.msg.task.request_id == walk.request_id && s.msg.task.state != flsd_msgs_TASK_RUNNING; },
      5s);
  ASSERT_TRUE(stopped);
  EXPECT_EQ(stopped->msg.task.state, flsd_msgs_TASK_CANCELLED);
  EXPECT_EQ(stopped->msg.faults, 0u);
}

TEST_F(SkilldTest, StateArrivesAtTheControlRate) {
  StartServer();
  auto client = Connect();
  const auto first = client->WaitForState([](const StateSample&) { return true; }, 5s);
  ASSERT_TRUE(first);
  std::this_thread::sleep_for(1s);
  const auto later = client->LatestState();
  const double ticks_per_second = static_cast<double>(later->msg.tick - first->msg.tick) / 1.0;
  EXPECT_NEAR(ticks_per_second, 50.0, 6.0);
  EXPECT_NEAR(later->msg.time - first->msg.time, (later->msg.tick - first->msg.tick) * 0.02, 1e-9);
}

TEST_F(SkilldTest, OnlyTheControllerMovesTheRobotButAnyoneMayDamp) {
  StartServer();
  auto owner = Connect();
  auto observer = Connect();
  ASSERT_TRUE(owner->AcquireControl().ok());
  const CallResult refused = observer->Call("stand");
  EXPECT_EQ(refused.status, flsd_msgs_STATUS_NOT_IN_CONTROL);
  EXPECT_THAT(refused.message, HasSubstr(owner->id()));
  EXPECT_EQ(observer->AcquireControl().status, ReplyStatus::kNotInControl);

  ASSERT_TRUE(owner->Call("stand").ok());
  ASSERT_TRUE(owner->WaitForState(Standing, 10s));
  ASSERT_TRUE(observer->Call("damp").ok());
  const auto damped = observer->WaitForState([](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_DAMP; }, 5s);
  ASSERT_TRUE(damped);
  EXPECT_THAT(damped->fault_message, HasSubstr("emergency stop"));
  // The owner hears of the stop in its next reply.
  const CallResult next = owner->Call("status");
  EXPECT_THAT(next.safety_report, HasSubstr("emergency stop"));
}

TEST_F(SkilldTest, BadRequestsAreAnsweredAndFloodsCountedWhileTheServerRuns) {
  // The shipped config with 20 requests per second and a burst of 10 for each client instead of
  // 1000 and 100. The request topic keeps the last 64 samples, so on a busy machine the server
  // may see only 64 of a flood: more than 10, never more than 100.
  std::string config = testutil::ReadFile(FLSD_SOURCE_DIR "/configs/server.yaml");
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"requests_per_second: 1000", "requests_per_second: 20"},
                                 {"request_burst: 100", "request_burst: 10"}}) {
    ASSERT_NE(config.find(from), std::string::npos) << "configs/server.yaml has no '" << from << "'";
    config.replace(config.find(from), from.size(), to);
  }
  const testutil::TempFile slow_config(".yaml", config);
  StartServer("sim", slow_config.path());
  auto client = Connect();
  ASSERT_TRUE(client->AcquireControl().ok());
  CallArgs bad;
  bad.skill = 1000;
  bad.duration = 1.0;
  EXPECT_EQ(client->Call("execute_skill", bad).status, flsd_msgs_STATUS_INVALID_ARGUMENT);
  bad.skill = 0;
  bad.duration = NAN;
  EXPECT_EQ(client->Call("execute_skill", bad).status, flsd_msgs_STATUS_INVALID_ARGUMENT);
  EXPECT_EQ(client->Call("self_destruct").status, flsd_msgs_STATUS_UNKNOWN_CALL);

  // A flood from a raw writer, faster than any client should send.
  dds::Domain domain(domain_, partition_);
  dds::Writer<flsd_msgs_Request> writer(domain, flsd_msgs_Request_desc, dds::kRequestTopic, dds::kRequestQos);
  for (int i = 0; i < 500 && writer.matched_readers() == 0; ++i) std::this_thread::sleep_for(10ms);
  std::string id = "flooder", call = "status";
  for (uint64_t n = 1; n <= 2000; ++n) {
    flsd_msgs_Request r{};
    r.header.client_id = id.data();
    r.header.request_id = n;
    r.call = call.data();
    r.map_yaml = const_cast<char*>("");
    writer.Write(r);
  }
  const auto counted =
      client->WaitForState([](const StateSample& s) { return s.msg.requests_dropped > 0; }, 10s);
  ASSERT_TRUE(counted) << "no dropped requests were counted";
  EXPECT_TRUE(client->Call("status").ok());
  EXPECT_EQ(client->LatestState()->controller, client->id());  // control kept through the flood
}

TEST_F(SkilldTest, ASilentControllerLosesTheLeaseAndTheRobotStands) {
  StartServer();
  auto client = Connect(/*heartbeat=*/std::chrono::hours(1));  // renews never
  ASSERT_TRUE(client->AcquireControl().ok());
  CallArgs args;
  args.skill = 0;
  args.duration = 60.0;
  ASSERT_TRUE(client->Call("execute_skill", args).ok());
  const auto lost = client->WaitForState(
      [](const StateSample& s) { return s.msg.task.state == flsd_msgs_TASK_LEASE_LOST; }, 10s);
  ASSERT_TRUE(lost);
  EXPECT_THAT(lost->task_message, HasSubstr("lapsed"));
  EXPECT_EQ(lost->controller, "");
}

TEST_F(SkilldTest, AClientReconnectsToARestartedServer) {
  StartServer();
  auto client = Connect();
  ASSERT_TRUE(client->AcquireControl().ok());
  server_->Signal(SIGTERM);
  ASSERT_EQ(server_->Wait(), 0) << server_->Log();
  EXPECT_FALSE(client->Call("status", {}, 300ms).answered);

  StartServer();
  ASSERT_TRUE(client->WaitForServer(15s)) << server_->Log();
  // The new server knows nothing of the old lease; the heartbeat learns so and does not re-take it.
  EXPECT_EQ(client->Call("stand").status, flsd_msgs_STATUS_NOT_IN_CONTROL);
  for (int i = 0; i < 100 && !client->lost_control(); ++i) std::this_thread::sleep_for(20ms);
  EXPECT_TRUE(client->lost_control());
  EXPECT_TRUE(client->AcquireControl().ok());
  EXPECT_TRUE(client->Call("stand").ok());
}

TEST_F(SkilldTest, SigtermDampsTheRobotAndExitsCleanly) {
  StartServer();
  auto client = Connect();
  client.reset();
  server_->Signal(SIGTERM);
  EXPECT_EQ(server_->Wait(), 0) << server_->Log();
  EXPECT_THAT(server_->Log(), HasSubstr("damping the robot"));
}

TEST_F(SkilldTest, AMissingLibraryIsABadInputExitNamingTheFile) {
  const auto [code, log] = testutil::RunProgram(
      testutil::BinaryPath("skilld"), {"--library", "/nonexistent/lib.safetensors", "--domain", "0"},
      testutil::UniqueTempPath("skilld.log"));
  EXPECT_EQ(code, 2);
  EXPECT_THAT(log, HasSubstr("/nonexistent/lib.safetensors"));
}

}  // namespace
}  // namespace flsd
