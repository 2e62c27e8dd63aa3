// skillctl against the real skilld: what it prints and the exit code a script relies on.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <csignal>

#include "client/client.h"
#include "tests/common/skilld_fixture.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;

class SkillctlTest : public testutil::SkilldFixture {};

TEST_F(SkillctlTest, WithoutAServerItSaysSoAndExitsTwo) {
  const auto [code, out] = testutil::RunProgram(testutil::BinaryPath("skillctl"),
                                                {"--domain", std::to_string(domain_), "--partition", partition_,
                                                 "--timeout", "0.5", "status"},
                                                testutil::UniqueTempPath("skillctl.log"));
  EXPECT_EQ(code, 2);
  EXPECT_THAT(out, HasSubstr("no skilld answers on DDS domain " + std::to_string(domain_)));
}

TEST_F(SkillctlTest, AScriptedSessionGetsTheExitCodesItExpects) {
  StartServer();
  auto [code, out] = Skillctl({"list"});
  EXPECT_EQ(code, 0) << out;
  EXPECT_THAT(out, HasSubstr("survival"));

  std::tie(code, out) = Skillctl({"skill", "1", "--duration", "1.5"});
  EXPECT_EQ(code, 0) << out;
  EXPECT_THAT(out, HasSubstr("execute_skill succeeded"));

  std::tie(code, out) = Skillctl({"skill", "99", "--duration", "1"});
  EXPECT_EQ(code, 1) << out;
  EXPECT_THAT(out, HasSubstr("skill 99 is not in [0, "));

  // The task runs to an outcome: done (0), or stopped by the supervisor (4), which this
  // library's selector can provoke (see docs/selector.md); never a hang or a refusal.
  std::tie(code, out) = Skillctl({"vel", "0.5", "0", "0", "--duration", "1"});
  EXPECT_TRUE(code == 0 || code == 4) << out;
  EXPECT_THAT(out, ::testing::AnyOf(HasSubstr("track_velocity succeeded"), HasSubstr("track_velocity safety stop")));
  // After a safety stop the robot may lie on its side, where stand is refused: put it back.
  std::tie(code, out) = Skillctl({"reset"});
  EXPECT_EQ(code, 0) << out;
  std::tie(code, out) = Skillctl({"stand"});
  EXPECT_EQ(code, 0) << out;

  // A goal walled in: the navigation ends with no path, a failed task (exit 4).
  std::tie(code, out) = Skillctl({"goto", "3", "3", "--map", FLSD_SOURCE_DIR "/configs/maps/enclosed.yaml"});
  EXPECT_EQ(code, 4) << out;
  EXPECT_THAT(out, HasSubstr("navigate no path"));

  // The emergency stop latches until whoever pressed it clears it (here the same --id).
  std::tie(code, out) = Skillctl({"--id", "operator", "damp"});
  EXPECT_EQ(code, 0) << out;
  std::tie(code, out) = Skillctl({"skill", "0", "--duration", "1"});
  EXPECT_EQ(code, 1) << out;
  EXPECT_THAT(out, HasSubstr("an emergency stop from operator is latched"));
  std::tie(code, out) = Skillctl({"stand"});
  EXPECT_EQ(code, 1) << out;
  std::tie(code, out) = Skillctl({"clear"});
  EXPECT_EQ(code, 1) << out;  // another client, before the hold time
  std::tie(code, out) = Skillctl({"--id", "operator", "clear"});
  EXPECT_EQ(code, 0) << out;

  // A damped robot sinks where it stands and sometimes rolls onto its side; put it back before
  // standing it up.
  std::tie(code, out) = Skillctl({"reset"});
  EXPECT_EQ(code, 0) << out;
  std::tie(code, out) = Skillctl({"stand"});
  EXPECT_EQ(code, 0) << out;
  std::tie(code, out) = Skillctl({"status"});
  EXPECT_EQ(code, 0) << out;
  EXPECT_THAT(out, HasSubstr("mode stand"));
  EXPECT_THAT(out, HasSubstr("faults none"));
}

TEST_F(SkillctlTest, KillingSkillctlMidSkillLetsTheLeaseLapseAndTheRobotStand) {
  StartServer();
  Client::Options options;
  options.domain_id = domain_;
  options.partition = partition_;
  Client observer(options);
  ASSERT_TRUE(observer.WaitForServer(std::chrono::seconds(15)));

  testutil::Process skillctl(testutil::BinaryPath("skillctl"), SkillctlArgs({"skill", "0", "--duration", "60"}),
                             testutil::UniqueTempPath("skillctl.log"));
  const auto running = observer.WaitForState(
      [](const StateSample& s) { return s.msg.mode == flsd_msgs_MODE_SKILL; }, std::chrono::seconds(15));
  ASSERT_TRUE(running) << skillctl.Log();
  skillctl.Signal(SIGKILL);  // no release, no stop: the process is simply gone
  EXPECT_EQ(skillctl.Wait(), 128 + SIGKILL);

  const auto lapsed = observer.WaitForState(
      [](const StateSample& s) { return s.msg.task.state == flsd_msgs_TASK_LEASE_LOST; }, std::chrono::seconds(5));
  ASSERT_TRUE(lapsed);
  EXPECT_EQ(lapsed->msg.mode, flsd_msgs_MODE_STAND);
  EXPECT_EQ(lapsed->controller, "");
}

}  // namespace
}  // namespace flsd
