// The library make demo and skilld ship (models/a1_flsd.safetensors) keeps the simulated A1 up for
// 10 s with its three fastest skills, run as skilld runs them (PolicyRunner, Eigen, the library's
// target filter) on the nominal robot from its default pose, within the limits of skilld's
// supervisor; its skills are mirror images in pairs, and none fell in its evaluations.

#include <gtest/gtest.h>

#include "core/paths.h"
#include "robot/observation.h"
#include "server/safety.h"
#include "sim/env.h"
#include "skills/runtime/skill_library.h"
#include "tests/common/skill_choice.h"
#include "tests/common/served_termination.h"

namespace flsd {
namespace {

using testutil::TerminationOf;

void ExpectThreeFastestSkillsKeepTheRobotUpFor10s(const SkillLibrary& library) {
  const std::vector<int> skills = testutil::FastestSurvivingSkills(library, 3);
  ASSERT_EQ(skills.size(), 3u);

  EnvConfig config;
  config.randomization.DisableAll();
  config.reset.joint_pos_scale = {1.0, 1.0};
  config.reset.base_velocity = 0.0;
  config.termination = TerminationOf(SafetyConfig{});
  config.episode_steps = 10000;
  config.action_filter_hz = library.action_filter_hz();
  const MjModelPtr model = LoadMjModel(config.model);
  PolicyRunner policy(library);
  for (int n = 0; n < 3; ++n) {
    const int skill = skills[n];
    Env env(*model, config, 1);
    std::vector<float> motion(kMotionObsSize), action(kActionSize, 0.0f);
    std::vector<float> previous(kActionSize, 0.0f);
    // The path's length, not the displacement: a skill that turns as it goes walks a circle.
    double path = 0.0;
    for (int t = 0; t < 500; ++t) {  // 10 s at 50 Hz
      const Eigen::Vector3d before = env.state().base_position;
      BuildMotionObservation(env.state(), motion.data());
      policy.Act(motion.data(), previous.data(), skill, action.data());
      previous = action;
      const Termination ending = env.Step(action.data());
      ASSERT_FALSE(IsFailure(ending)) << "skill " << skill << " fell at step " << t << ": " << ToString(ending);
      path += (env.state().base_position - before).head<2>().norm();
    }
    EXPECT_GT(env.state().base_position.z(), 0.15) << "skill " << skill;
    // A skill the library describes as moving does move.
    EXPECT_GT(path, 0.5 * 10.0 * library.skills()[skill].mean_linear_velocity.head<2>().norm()) << "skill " << skill;
  }
}

TEST(ShippedLibrary, ThreeSkillsKeepTheRobotUpFor10s) {
  ExpectThreeFastestSkillsKeepTheRobotUpFor10s(SkillLibrary::Load(ResolveDataPath("models/a1_flsd.safetensors")));
}

// Skill k and its pair, as the library's evaluation measured them: the same forward speed, and
// sideways speed and turn rate of opposite signs, to 0.1.
TEST(ShippedLibrary, PairsMoveAsMirrorImages) {
  const SkillLibrary library = SkillLibrary::Load(ResolveDataPath("models/a1_flsd.safetensors"));
  int pairs = 0;
  for (const SkillDescriptor& d : library.skills()) {
    const SkillDescriptor& m = library.skills()[d.mirror_skill];
    pairs += d.mirror_skill != d.id;
    EXPECT_NEAR(d.mean_linear_velocity.x(), m.mean_linear_velocity.x(), 0.1) << "skill " << d.id;
    EXPECT_NEAR(d.mean_linear_velocity.y(), -m.mean_linear_velocity.y(), 0.1) << "skill " << d.id;
    EXPECT_NEAR(d.mean_angular_velocity.z(), -m.mean_angular_velocity.z(), 0.1) << "skill " << d.id;
  }
  EXPECT_EQ(pairs, 10);  // 5 mirror pairs and 4 self-paired skills
}

// The library ships no skill that skilld would refuse: each one survived its evaluation, and the
// randomised one from the worst of 8 starts, whose mean slip it records.
TEST(ShippedLibrary, NoSkillFellInEitherEvaluation) {
  const SkillLibrary library = SkillLibrary::Load(ResolveDataPath("models/a1_flsd.safetensors"));
  for (const SkillDescriptor& d : library.skills()) {
    EXPECT_FALSE(EarliestFall(d)) << "skill " << d.id;
    EXPECT_TRUE(d.randomized_survival_steps.has_value()) << "skill " << d.id;
    EXPECT_GT(d.randomized_stance_foot_speed.value_or(0.0), 0.0) << "skill " << d.id;
  }
}

}  // namespace
}  // namespace flsd
