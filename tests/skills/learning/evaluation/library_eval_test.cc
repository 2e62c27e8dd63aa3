// A library file rolled out by skilld's policy code reproduces what its export measured with the
// training code (libtorch, VecEnv), skill by skill, and is judged by the same bar.

#include "skills/learning/evaluation/library_eval.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/paths.h"
#include "skills/learning/evaluation/library_bar.h"

namespace flsd {
namespace {

TEST(EvaluateLibrary, TheShippedLibraryMovesAsItsDescriptorsSay) {
  const SkillLibrary library = SkillLibrary::Load(ResolveDataPath("models/a1_flsd.safetensors"));
  const Evaluation e = EvaluateLibrary(library, EvaluationOptions{});
  ASSERT_EQ(e.skills.size(), library.skills().size());
  EXPECT_EQ(e.steps, 1000);
  for (const SkillDescriptor& d : library.skills()) {
    SCOPED_TRACE("skill " + std::to_string(d.id));
    const SkillSummary& s = e.skills[d.id];
    EXPECT_FALSE(s.fell);
    // Float32 policies in two implementations drift apart over 20 s of a chaotic rollout, the more
    // the faster the skill: the 2 rad/s turn in place differs by 0.04 rad/s (2 %), its slip by 0.009.
    const auto within = [](double measured, double described, double floor, double share) {
      EXPECT_NEAR(measured, described, std::max(floor, share * std::abs(described)));
    };
    within(s.mean_linear_velocity[0], d.mean_linear_velocity.x(), 0.05, 0.04);
    within(s.mean_linear_velocity[1], d.mean_linear_velocity.y(), 0.05, 0.04);
    within(s.mean_angular_velocity[2], d.mean_angular_velocity.z(), 0.05, 0.04);
    EXPECT_NEAR(s.mean_base_height, d.mean_base_height, 0.01);
    ASSERT_TRUE(d.mean_stance_foot_speed.has_value());
    within(s.mean_stance_foot_speed, *d.mean_stance_foot_speed, 0.01, 0.15);
    EXPECT_EQ(e.mirror_skill[d.id], d.mirror_skill);
  }
  // The bar chooses the skills the served library offers for each direction.
  const LibraryBar bar = JudgeLibrary(e);
  EXPECT_EQ(bar.skill, DirectionSkills(library));
  EXPECT_EQ(bar.survivors, static_cast<int>(library.skills().size()));
  EXPECT_GT(bar.pooled_high_frequency_ratio, 0.0);
  EXPECT_EQ(EvaluationJson(e)["bar"]["pooled_high_frequency_ratio"], bar.pooled_high_frequency_ratio);
}

}  // namespace
}  // namespace flsd
