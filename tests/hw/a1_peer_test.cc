// The real skilld --backend hw against an A1 peer on loopback (the robot emulator, in this
// process, so that the test knows the moment a fault begins). For each fault the peer injects,
// once the robot stands: the mode on the state topic becomes damp within the fault's detection
// time plus a margin, the fault is reported in the next reply, and stand is refused naming the
// real cause. Faults present from the start stop skilld in pre-flight with their own message.
// Measured by the wall clock: its own label, run alone.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cctype>
#include <fstream>
#include <ostream>
#include <memory>

#include "emulator/a1_emulator.h"
#include "skills/runtime/skill_library.h"
#include "tests/common/client_skilld_fixture.h"
#include "tests/common/skill_choice.h"

namespace flsd {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;
using ::testing::Not;

class A1PeerTest : public testutil::ClientSkilldFixture {
 protected:
  void StartPeer(const hw::EmulatorFaults& faults = {}) {
    hw::EmulatorConfig config;
    config.port = 0;
    peer_ = std::make_unique<hw::A1Emulator>(config);
    peer_->SetFaults(faults);
    peer_->Start();
    const std::string path = testutil::UniqueTempPath("server.yaml");
    std::ofstream(path) << "hw:\n  local_host: 127.0.0.1\n  local_port: 0\n  robot_host: 127.0.0.1\n"
                        << "  robot_port: " << peer_->port() << "\n  preflight_seconds: 0.3\n";
    StartServer("hw", path);
  }
  void TearDown() override {
    server_.reset();
    if (peer_) peer_->Stop();
  }

  std::unique_ptr<hw::A1Emulator> peer_;
};

struct PeerFault {
  const char* name;
  hw::EmulatorFaults faults;
  const char* message;  // in the fault message and the refusal of stand
  double detect;        // s: the configured detection time (configs/server.yaml, hw:)
  bool lasts = true;    // still a fault once damped (late frames come again; encoders at rest may repeat)
  bool turning = false;  // injected while a skill turns the robot (a freeze of the encoders shows only then)
};

void PrintTo(const PeerFault& fault, std::ostream* out) { *out << fault.name; }

hw::EmulatorFaults Fault(void (*set)(hw::EmulatorFaults&)) {
  hw::EmulatorFaults f;
  set(f);
  return f;
}

class A1PeerFault : public A1PeerTest, public ::testing::WithParamInterface<PeerFault> {};

TEST_P(A1PeerFault, DampsWithinItsDetectionTimeAndRefusesStandNamingTheCause) {
  const PeerFault& fault = GetParam();
  StartPeer();
  auto client = Connect();
  ASSERT_TRUE(client->AcquireControl().ok());
  ASSERT_TRUE(client->Call("stand").ok());
  ASSERT_TRUE(client->WaitForState(
      [](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_STAND && s.msg.position[2] > 0.22; }, 10s))
      << server_->Log();
  std::this_thread::sleep_for(1s);  // settled
  if (fault.turning) {
    CallArgs turn;  // the library's fastest turn (the shipped one: an arc at about 0.5 rad/s)
    turn.skill = testutil::FastestTurningSkill(SkillLibrary::Load(FLSD_SOURCE_DIR "/models/a1_flsd.safetensors"));
    ASSERT_GE(turn.skill, 0);
    turn.duration = 10.0;
    ASSERT_TRUE(client->Call("execute_skill", turn).ok());
    ASSERT_TRUE(client->WaitForState([](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_SKILL; }, 20s));
    std::this_thread::sleep_for(500ms);
  }

  const auto injected = std::chrono::steady_clock::now();
  peer_->SetFaults(fault.faults);
  const auto damped = client->WaitForState([](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_DAMP; }, 5s);
  ASSERT_TRUE(damped) << fault.name << "\n" << server_->Log();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - injected).count();
  // Detection, then at most a control tick, a state sample, and scheduling on a busy machine.
  EXPECT_LT(seconds, fault.detect + 0.15) << fault.name;
  EXPECT_THAT(damped->fault_message, HasSubstr(fault.message));

  const CallResult status = client->Call("status");
  EXPECT_TRUE(status.ok());
  EXPECT_THAT(status.safety_report, HasSubstr(fault.message));
  EXPECT_FALSE(client->WaitForState([](const StateSample& s) { return s.msg.mode != flsd_msgs_MODE_DAMP; }, 300ms))
      << "the stop did not latch";
  if (!fault.lasts) return;
  const CallResult stand = client->Call("stand");
  EXPECT_EQ(stand.status, flsd_msgs_STATUS_SAFETY_STOP);
  EXPECT_THAT(stand.message, HasSubstr(std::string("cannot stand: backend: ") + fault.message));
  EXPECT_THAT(stand.message, Not(HasSubstr("upright"))) << "the robot stands; its backend is what is wrong";
}

INSTANTIATE_TEST_SUITE_P(
    Faults, A1PeerFault,
    ::testing::Values(
        PeerFault{"silent", Fault([](hw::EmulatorFaults& f) { f.silent = true; }), "no valid state frame from the robot", 0.1},
        PeerFault{"corrupt", Fault([](hw::EmulatorFaults& f) { f.corrupt_fraction = 1.0; }),
                  "no valid state frame from the robot", 0.1},
        PeerFault{"late", Fault([](hw::EmulatorFaults& f) { f.late_ms = 200.0; }), "no valid state frame from the robot",
                  0.1, false},
        PeerFault{"hung IMU", Fault([](hw::EmulatorFaults& f) { f.frozen_imu = true; }), "IMU readings frozen", 0.1},
        PeerFault{"hung encoders", Fault([](hw::EmulatorFaults& f) { f.frozen_joints = true; }),
                  "joint encoder readings frozen", 0.1, false, true},
        PeerFault{"dead motor", Fault([](hw::EmulatorFaults& f) { f.dead_motor = 7; }),
                  "motor RR_thigh_joint is not in servo mode", 0.05}),
    [](const ::testing::TestParamInfo<PeerFault>& info) {
      std::string name = info.param.name;
      for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return name;
    });

TEST_F(A1PeerTest, EveryFrameMalformedFromTheStartIsAPreflightFailureThatSaysSo) {
  hw::EmulatorFaults faults;
  faults.corrupt_fraction = 1.0;
  StartPeer(faults);
  EXPECT_EQ(server_->Wait(), 2) << server_->Log();
  EXPECT_THAT(server_->Log(), ::testing::ContainsRegex("[0-9]+ of [0-9]+ state frames were malformed"));
  EXPECT_THAT(server_->Log(), HasSubstr("firmware or frame-size mismatch"));
  EXPECT_THAT(server_->Log(), Not(HasSubstr("no state frame from the robot")));
}

TEST_F(A1PeerTest, AMotorOutOfServoModeFromTheStartIsAPreflightFailure) {
  hw::EmulatorFaults faults;
  faults.dead_motor = 7;
  StartPeer(faults);
  EXPECT_EQ(server_->Wait(), 2) << server_->Log();
  EXPECT_THAT(server_->Log(), HasSubstr("RR_thigh_joint motor reports mode 0x00, not servo mode (0x0A)"));
}

}  // namespace
}  // namespace flsd
