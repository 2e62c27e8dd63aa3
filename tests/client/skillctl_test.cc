// skillctl against the real skilld: what it prints and the exit code a script relies on.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

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

  std::tie(code, out) = Skillctl({"vel", "0.5", "0", "0", "--duration", "1"});
  EXPECT_EQ(code, 1) << out;
  EXPECT_THAT(out, HasSubstr("not available"));

  std::tie(code, out) = Skillctl({"damp"});
  EXPECT_EQ(code, 0) << out;
  std::tie(code, out) = Skillctl({"skill", "0", "--duration", "1"});
  EXPECT_EQ(code, 1) << out;
  EXPECT_THAT(out, HasSubstr("safety stop"));

  std::tie(code, out) = Skillctl({"stand"});
  EXPECT_EQ(code, 0) << out;
  std::tie(code, out) = Skillctl({"status"});
  EXPECT_EQ(code, 0) << out;
  EXPECT_THAT(out, HasSubstr("mode stand"));
  EXPECT_THAT(out, HasSubstr("faults none"));
}

}  // namespace
}  // namespace flsd
