// ComposeLibraries: skills joined from several libraries run exactly as they did in their own,
// keep their descriptors and mirror pairs, and what cannot be joined is refused by name.

#include "skills/learning/export/compose_library.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "skills/runtime/skill_library.h"
#include "tests/common/malloc_counter.h"
#include "tests/common/test_support.h"
#include "tests/skills/runtime/test_libraries.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;
using testutil::InputErrorMessage;
using testutil::UniqueTempPath;

// The action of `skill` in `library` for one fixed observation.
std::vector<float> ActionOf(const SkillLibrary& library, int skill) {
  std::vector<float> motion(kMotionObsSize), previous(kActionSize), action(kActionSize);
  for (int i = 0; i < kMotionObsSize; ++i) motion[i] = 0.1f * static_cast<float>(i % 7) - 0.3f;
  for (int i = 0; i < kActionSize; ++i) previous[i] = 0.05f * static_cast<float>(i) - 0.2f;
  PolicyRunner runner(library);
  runner.Act(motion.data(), previous.data(), skill, action.data());
  return action;
}

class ComposeLibraryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // a: 4 skills, pairs (0, 2) and (1, 3); b: 5 skills, pairs (0, 2) and (1, 3), 4 alone.
    testutil::WriteTestLibrary(a_, testutil::SmallLibraryConfig(4), testutil::RandomPolicy(testutil::SmallLibraryConfig(4), 3));
    testutil::WriteTestLibrary(b_, testutil::SmallLibraryConfig(5), testutil::RandomPolicy(testutil::SmallLibraryConfig(5), 5));
  }
  void TearDown() override {
    for (const std::string& path : {a_, b_, out_}) std::remove(path.c_str());
  }
  std::string a_ = UniqueTempPath("a.safetensors"), b_ = UniqueTempPath("b.safetensors"),
              out_ = UniqueTempPath("out.safetensors");
};

TEST_F(ComposeLibraryTest, JoinedSkillsRunAsInTheirOwnLibraries) {
  const nlohmann::json result = ComposeLibraries({ParseLibraryPart(a_ + ":2,0"), ParseLibraryPart(b_)}, out_);
  EXPECT_EQ(result["num_skills"], 7);
  EXPECT_EQ(result["policies"], 2);
  const SkillLibrary joined = SkillLibrary::Load(out_), a = SkillLibrary::Load(a_), b = SkillLibrary::Load(b_);
  // New ids in the order chosen: a's 2 and 0, then b's 0 to 4.
  const int from_part[7] = {0, 0, 1, 1, 1, 1, 1};
  const int from_skill[7] = {2, 0, 0, 1, 2, 3, 4};
  for (int k = 0; k < 7; ++k) {
    const SkillLibrary& source = from_part[k] == 0 ? a : b;
    EXPECT_EQ(ActionOf(joined, k), ActionOf(source, from_skill[k])) << k;
    EXPECT_EQ(joined.skills()[k].policy, from_part[k]) << k;
    EXPECT_EQ(joined.skills()[k].policy_skill, from_skill[k]) << k;
    EXPECT_EQ(joined.skills()[k].survival_steps, 1000 - from_skill[k]) << k;
    EXPECT_EQ(result["skills_from"][k]["skill"], from_skill[k]);
  }
  EXPECT_NE(ActionOf(a, 0), ActionOf(b, 0));  // the two policies differ, so the checks above mean something
  // Mirror pairs stay pairs under the new ids.
  const int mirror[7] = {1, 0, 4, 5, 2, 3, 6};
  for (int k = 0; k < 7; ++k) EXPECT_EQ(joined.skills()[k].mirror_skill, mirror[k]) << k;
  EXPECT_EQ(joined.metadata()["policies"][0]["source"]["fingerprint"], a.fingerprint());
  EXPECT_EQ(joined.metadata()["policies"][1]["source"]["fingerprint"], b.fingerprint());
  EXPECT_EQ(joined.metadata()["composed_from"][1]["library"], a_);
}

// A composed library composes again, and a version 1 library joins as one policy.
TEST_F(ComposeLibraryTest, ComposedAndVersion1LibrariesJoin) {
  const std::string v1 = UniqueTempPath("v1.safetensors"), twice = UniqueTempPath("twice.safetensors");
  testutil::WriteAsVersion1(b_, v1);
  ComposeLibraries({ParseLibraryPart(a_), ParseLibraryPart(v1 + ":4")}, out_);
  ComposeLibraries({ParseLibraryPart(out_ + ":4"), ParseLibraryPart(a_ + ":1,3")}, twice);
  const SkillLibrary joined = SkillLibrary::Load(twice);
  ASSERT_EQ(joined.num_skills(), 3);
  EXPECT_EQ(joined.policies().size(), 2u);
  EXPECT_EQ(ActionOf(joined, 0), ActionOf(SkillLibrary::Load(b_), 4));
  EXPECT_EQ(ActionOf(joined, 2), ActionOf(SkillLibrary::Load(a_), 3));
  EXPECT_EQ(joined.skills()[0].mirror_skill, 0);
  EXPECT_EQ(joined.skills()[1].mirror_skill, 2);
  std::remove(v1.c_str());
  std::remove(twice.c_str());
}

// Two policies of different sizes, one skill after the other: still no heap allocation per act.
TEST_F(ComposeLibraryTest, ActingAcrossPoliciesAllocatesNothing) {
  ComposeLibraries({ParseLibraryPart(a_), ParseLibraryPart(b_)}, out_);
  const SkillLibrary joined = SkillLibrary::Load(out_);
  PolicyRunner runner(joined);
  std::vector<float> motion(kMotionObsSize, 0.2f), previous(kActionSize, 0.1f), action(kActionSize);
  runner.Act(motion.data(), previous.data(), 0, action.data());
  EXPECT_EQ(testutil::CountMallocs([&] {
              for (int i = 0; i < 100; ++i) runner.Act(motion.data(), previous.data(), i % 9, action.data());
            }),
            0);
}

TEST_F(ComposeLibraryTest, RefusesWhatCannotBeJoinedAndWritesNothing) {
  auto error = [&](const std::vector<LibraryPart>& parts) {
    return InputErrorMessage([&] { ComposeLibraries(parts, out_); });
  };
  EXPECT_THAT(error({ParseLibraryPart(a_ + ":0")}),
              HasSubstr(a_ + ": skill 0 is chosen but its mirror image, skill 2, is not"));
  EXPECT_THAT(error({ParseLibraryPart(a_ + ":0,2,0")}), HasSubstr("skill 0 is chosen twice"));
  EXPECT_THAT(error({ParseLibraryPart(a_ + ":4")}), HasSubstr(a_ + ": has no skill 4 (it has 0 to 3)"));
  EXPECT_THAT(error({}), HasSubstr("give at least one library"));
  EXPECT_THAT(error({ParseLibraryPart(a_ + ":0,2"), ParseLibraryPart(a_ + ":2,0")}),
              HasSubstr(a_ + ": skill 2 is already chosen from " + a_));
  EXPECT_THAT(InputErrorMessage([&] { ComposeLibraries({ParseLibraryPart(a_)}, a_); }),
              HasSubstr(a_ + ": is also an input"));
  EXPECT_THAT(error({ParseLibraryPart("/nonexistent/lib.safetensors")}), HasSubstr("/nonexistent/lib.safetensors"));
  TrainConfig filtered = testutil::SmallLibraryConfig(4);
  filtered.env.action_filter_hz = 4.0;
  testutil::WriteTestLibrary(b_, filtered, testutil::RandomPolicy(filtered));
  EXPECT_THAT(error({ParseLibraryPart(a_), ParseLibraryPart(b_)}), HasSubstr("one library runs one filter"));
  EXPECT_FALSE(std::filesystem::exists(out_));
  EXPECT_THAT(InputErrorMessage([] { ParseLibraryPart("lib.safetensors:1,x"); }), HasSubstr("found 'x'"));
  EXPECT_THAT(InputErrorMessage([] { ParseLibraryPart("lib.safetensors:1,,2"); }), HasSubstr("found ''"));
  EXPECT_THAT(InputErrorMessage([] { ParseLibraryPart("lib.safetensors:-1"); }), HasSubstr("found '-1'"));
  EXPECT_TRUE(ParseLibraryPart("lib.safetensors").skills.empty());
}

}  // namespace
}  // namespace flsd
