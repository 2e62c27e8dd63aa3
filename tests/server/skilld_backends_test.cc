// One client script, unchanged, against `skilld --backend sim` and `skilld --backend hw` (the
// real A1's UDP path, with the robot emulator on loopback). Injected faults on the hardware path
// are tests/hw/a1_peer_test.cc's.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "skills/runtime/skill_library.h"
#include "tests/common/client_skilld_fixture.h"
#include "tests/common/skill_choice.h"

namespace flsd {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

class SkilldBackendTest : public testutil::ClientSkilldFixture {
 protected:
  // Starts the emulator binary, then skilld --backend hw.
  void StartHw() {
    emulator_ = std::make_unique<testutil::Process>(testutil::BinaryPath("a1_emulator"),
                                                    std::vector<std::string>{"--port", "0"},
                                                    testutil::UniqueTempPath("emulator.log"));
    int port = 0;
    for (int i = 0; i < 500 && port == 0; ++i) {
      std::smatch m;
      const std::string log = emulator_->Log();
      if (std::regex_search(log, m, std::regex("listening on 127.0.0.1:(\\d+)"))) port = std::stoi(m[1]);
      std::this_thread::sleep_for(10ms);
    }
    ASSERT_NE(port, 0) << emulator_->Log();
    config_path_ = testutil::UniqueTempPath("server.yaml");
    std::ofstream(config_path_) << "hw:\n  local_host: 127.0.0.1\n  local_port: 0\n  robot_host: 127.0.0.1\n"
                                << "  robot_port: " << port << "\n  preflight_seconds: 0.3\n";
    StartServer("hw", config_path_);
  }
  void Start(const std::string& backend) {
    if (backend == "hw") StartHw(); else StartServer();
  }

  std::unique_ptr<testutil::Process> emulator_;
  std::string config_path_;
};

class SameScript : public SkilldBackendTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(SameScript, StandRunASkillStopAndDamp) {
  Start(GetParam());
  auto client = Connect();
  ASSERT_TRUE(client->AcquireControl().ok());
  ASSERT_TRUE(client->Call("stand").ok());
  const auto standing = client->WaitForState(
      [](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_STAND && s.msg.position[2] > 0.22; }, 10s);
  ASSERT_TRUE(standing) << server_->Log();
  EXPECT_EQ(standing->backend, GetParam());

  // The calmest straight walk (see CalmestStraightSkill for why).
  CallArgs args;
  args.skill = testutil::CalmestStraightSkill(SkillLibrary::Load(FLSD_SOURCE_DIR "/models/a1_flsd.safetensors"));
  ASSERT_GE(args.skill, 0);
  args.duration = 2.0;
  ASSERT_TRUE(client->Call("execute_skill", args).ok());
  const auto done = client->WaitForState(
      [](const StateSample& s) { return s.task_call == "execute_skill" && s.msg.task.state != flsd_msgs_TASK_RUNNING; },
      30s);
  ASSERT_TRUE(done) << client->LatestState()->task_message;
  EXPECT_EQ(done->msg.task.state, flsd_msgs_TASK_SUCCEEDED) << done->task_message << " " << done->fault_message;

  // Back to back: it starts once the robot stands as it should (lying down and up again if need be).
  args.duration = 30.0;
  ASSERT_TRUE(client->Call("execute_skill", args).ok());
  ASSERT_TRUE(client->WaitForState([](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_SKILL; }, 20s))
      << client->LatestState()->task_message;
  ASSERT_TRUE(client->Call("stop").ok());
  const auto stopped = client->WaitForState(
      [](const StateSample& s) { return s.msg.task.state == flsd_msgs_TASK_CANCELLED; }, 5s);
  ASSERT_TRUE(stopped);
  EXPECT_EQ(stopped->msg.mode, flsd_msgs_MODE_STAND);
  ASSERT_TRUE(client->Call("damp").ok());
  EXPECT_TRUE(client->WaitForState([](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_DAMP; }, 5s));
}

INSTANTIATE_TEST_SUITE_P(Backends, SameScript, ::testing::Values("sim", "hw"));

}  // namespace
}  // namespace flsd
