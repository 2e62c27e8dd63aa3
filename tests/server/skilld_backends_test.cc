// One client script, unchanged, against `skilld --backend sim` and `skilld --backend hw` (the
// real A1's UDP path, with the robot emulator on loopback); and on the hardware path, injected
// faults end in a reported damping stop while the server keeps answering.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "client/client.h"
#include "tests/common/skilld_fixture.h"

namespace flsd {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

class SkilldBackendTest : public testutil::SkilldFixture {
 protected:
  // Starts the emulator (with `faults`, after `faults_after` seconds), then skilld --backend hw.
  void StartHw(const std::vector<std::string>& faults = {}) {
    std::vector<std::string> args = {"--port", "0"};
    args.insert(args.end(), faults.begin(), faults.end());
    emulator_ = std::make_unique<testutil::Process>(testutil::BinaryPath("a1_emulator"), args,
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
  std::unique_ptr<Client> Connect() {
    Client::Options options;
    options.domain_id = domain_;
    options.partition = partition_;
    auto client = std::make_unique<Client>(options);
    EXPECT_TRUE(client->WaitForServer(15s)) << server_->Log();
    return client;
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

  CallArgs args;
  args.skill = 3;
  args.duration = 2.0;
  ASSERT_TRUE(client->Call("execute_skill", args).ok());
  const auto done = client->WaitForState(
      [](const StateSample& s) { return s.task_call == "execute_skill" && s.msg.task.state != flsd_msgs_TASK_RUNNING; },
      10s);
  ASSERT_TRUE(done);
  EXPECT_EQ(done->msg.task.state, flsd_msgs_TASK_SUCCEEDED) << done->task_message << " " << done->fault_message;

  args.duration = 30.0;
  ASSERT_TRUE(client->Call("execute_skill", args).ok());
  ASSERT_TRUE(client->WaitForState([](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_SKILL; }, 5s));
  ASSERT_TRUE(client->Call("stop").ok());
  const auto stopped = client->WaitForState(
      [](const StateSample& s) { return s.msg.task.state == flsd_msgs_TASK_CANCELLED; }, 5s);
  ASSERT_TRUE(stopped);
  EXPECT_EQ(stopped->msg.mode, flsd_msgs_MODE_STAND);
  ASSERT_TRUE(client->Call("damp").ok());
  EXPECT_TRUE(client->WaitForState([](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_DAMP; }, 5s));
}

INSTANTIATE_TEST_SUITE_P(Backends, SameScript, ::testing::Values("sim", "hw"));

class HwFault : public SkilldBackendTest, public ::testing::WithParamInterface<std::pair<std::string, std::string>> {};

TEST_P(HwFault, EndsInAReportedDampingStopWithTheServerStillAnswering) {
  const auto& [flag, expected] = GetParam();
  std::vector<std::string> faults = {"--faults-after", "4"};
  std::istringstream words(flag);
  for (std::string w; words >> w;) faults.push_back(w);
  StartHw(faults);
  auto client = Connect();
  ASSERT_TRUE(client->AcquireControl().ok());
  ASSERT_TRUE(client->Call("stand").ok());
  const auto tripped = client->WaitForState([](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_DAMP; }, 15s);
  ASSERT_TRUE(tripped) << server_->Log();
  EXPECT_THAT(tripped->fault_message, HasSubstr(expected));
  EXPECT_NE(tripped->msg.faults, 0u);
  const CallResult status = client->Call("status");
  EXPECT_TRUE(status.ok());
  EXPECT_THAT(status.safety_report, HasSubstr(expected));
}

INSTANTIATE_TEST_SUITE_P(
    Faults, HwFault,
    ::testing::Values(std::make_pair("--drop 1", "backend: no valid state frame from the robot"),
                      std::make_pair("--corrupt 1", "backend: no valid state frame from the robot"),
                      std::make_pair("--late-ms 200", "backend: no valid state frame from the robot"),
                      std::make_pair("--frozen", "backend: IMU and joint readings frozen"),
                      std::make_pair("--dead-motor 7", "backend: motor RR_thigh_joint is not in servo mode")));

}  // namespace
}  // namespace flsd
