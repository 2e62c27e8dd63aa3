// Switching between every ordered pair of the shipped library's dependable skills: every pair is
// run once, each skill also from a stand, and a started skill moves as its descriptor says.

#include "skills/learning/evaluation/transition_eval.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "core/paths.h"
#include "skills/learning/evaluation/tracking_eval.h"
#include "skills/runtime/nearest_skill.h"

namespace flsd {
namespace {

TEST(EvaluateTransitions, RunsEveryOrderedPairAndEachSkillFromAStand) {
  const SkillLibrary library = SkillLibrary::Load(ResolveDataPath("models/a1_flsd.safetensors"));
  const TransitionEvaluation e = EvaluateTransitions(library, TrainingEnvOf(library), 0.5, 2.0, 1.0, 1);
  const std::vector<int> skills = NearestSkillSelector(library).candidates();
  const int n = static_cast<int>(skills.size());
  ASSERT_EQ(e.skills, skills);
  EXPECT_EQ(e.pairs, n * (n - 1));
  ASSERT_EQ(e.results.size(), static_cast<size_t>(n * n));  // n - 1 sources and the stand per target
  EXPECT_EQ(std::accumulate(e.falls_into.begin(), e.falls_into.end(), 0), e.falls);
  // The fastest backward skill started from a stand: no fall, and after a second of it within 25 %
  // of the speed its descriptor records.
  const SkillDescriptor* fastest = nullptr;
  for (int id : skills) {
    const SkillDescriptor& d = library.skills()[id];
    if (!fastest || d.mean_linear_velocity.x() < fastest->mean_linear_velocity.x()) fastest = &d;
  }
  for (const TransitionResult& r : e.results) {
    if (r.from != -1 || r.to != fastest->id) continue;
    EXPECT_FALSE(r.fell);
    EXPECT_NEAR(r.achieved[0], fastest->mean_linear_velocity.x(), 0.25 * std::abs(fastest->mean_linear_velocity.x()));
  }
  const nlohmann::json json = TransitionJson(e);
  EXPECT_EQ(json["results"][0]["from"], "stand");
  EXPECT_EQ(json["pairs"], e.pairs);
}

}  // namespace
}  // namespace flsd
