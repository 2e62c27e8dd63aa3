// The parts of a learned semi-MDP selector that training and skilld share: its memory (the
// running skill, the times since a switch and a new command, the window's mean velocity error) and
// its prior (the masks, and the nearest-skill or time-sharing prior), on libraries of known
// descriptors; and the one factory that builds every selector.

#include "skills/runtime/selector.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "robot/observation.h"
#include "skills/runtime/selector_memory.h"
#include "tests/skills/runtime/test_libraries.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;

// o^m of a robot moving at (vx, vy, wz), as the observation scales it.
std::vector<float> MovingAt(double vx, double vy, double wz) {
  std::vector<float> motion(kMotionObsSize, 0.0f);
  motion[0] = static_cast<float>(vx * kMotionObsLayout[0].scale);
  motion[1] = static_cast<float>(vy * kMotionObsLayout[0].scale);
  motion[5] = static_cast<float>(wz * kMotionObsLayout[1].scale);
  return motion;
}

TEST(SelectorMemory, AveragesTheVelocityOverItsWindowSinceTheCommandChanged) {
  SelectorMemory memory(4);
  const double forward[3] = {0.5, 0.0, 0.0};
  EXPECT_EQ(memory.WindowError(), Eigen::Vector3d::Zero());
  memory.Reset(2);
  EXPECT_EQ(memory.running(), 2);
  const std::vector<float> slow = MovingAt(0.2, 0.0, 0.0), fast = MovingAt(0.8, 0.1, -0.4);
  for (int t = 0; t < 3; ++t) memory.Record(forward, 2, slow.data());
  EXPECT_NEAR(memory.WindowError().x(), 0.3, 1e-6);
  EXPECT_NEAR(memory.seconds_since_switch(), 0.06, 1e-9);  // kept running skill 2 from the reset
  // The window holds the last four steps: 0.2, 0.8, 0.8, 0.8.
  for (int t = 0; t < 3; ++t) memory.Record(forward, 3, fast.data());
  EXPECT_NEAR(memory.WindowError().x(), 0.5 - 0.65, 1e-6);
  EXPECT_NEAR(memory.WindowError().y(), -0.075, 1e-6);
  EXPECT_NEAR(memory.WindowError().z(), 0.3, 1e-6);
  EXPECT_EQ(memory.running(), 3);
  EXPECT_EQ(memory.previous(), 2);
  EXPECT_NEAR(memory.seconds_since_switch(), 0.06, 1e-9);
  EXPECT_NEAR(memory.seconds_since_command(), 0.12, 1e-9);
  // A command that wavers within TimeSharingSelector::kNewCommand keeps the window; the error is
  // against the latest command.
  const double wavering[3] = {0.55, 0.0, 0.0};
  memory.Record(wavering, 3, fast.data());
  EXPECT_NEAR(memory.WindowError().x(), 0.55 - 0.8 + 0.0, 1e-6);
  EXPECT_NEAR(memory.seconds_since_command(), 0.14, 1e-9);
  // A new command starts a new window.
  const double turn[3] = {0.0, 0.0, 1.0};
  memory.Record(turn, 3, slow.data());
  EXPECT_NEAR(memory.WindowError().x(), -0.2, 1e-6);
  EXPECT_NEAR(memory.WindowError().z(), 1.0, 1e-6);
  EXPECT_NEAR(memory.seconds_since_command(), 0.02, 1e-9);

  std::vector<float> features(SelectorMemory::FeatureSize(5), -1.0f);
  memory.WriteFeatures(5, features.data());
  using testing::FloatNear;
  EXPECT_THAT(features, testing::ElementsAre(FloatNear(0.1f, 1e-6), FloatNear(0.02f, 1e-6), FloatNear(-0.2f, 1e-6),
                                             0.0f, FloatNear(1.0f, 1e-6), 0, 0, 0, 1, 0));
  memory.Reset();
  EXPECT_EQ(memory.running(), -1);
  EXPECT_EQ(memory.previous(), -1);
  EXPECT_EQ(memory.seconds_since_command(), 0.0);
}

TEST(SelectorPrior, MasksWhatSkilldMasksAndFavoursTheTimeSharingChoice) {
  // Skill 3 fell in its randomised evaluation; the library records a fall on the switch 1 -> 2,
  // and on the cycle 2, 1, 0 played for several periods.
  const std::string path = testutil::WriteLibraryWithFallingSwitches(
      {{0, 0, 0}, {0.4, 0, 0}, {0.7, 0, 0}, {0.5, 0, 0}}, {{1, 2}}, {{2, 1, 0}});
  SkillLibrary library = SkillLibrary::Load(path);
  std::remove(path.c_str());
  const_cast<SkillDescriptor&>(library.skills()[3]).randomized_fell = true;
  EXPECT_FALSE(Dependable(library.skills()[3]));
  const double forward[3] = {0.5, 0.0, 0.0};
  std::vector<float> logits(4);
  constexpr float kOut = NearestSkillSelector::kExcludedLogit;

  SelectorPrior masks(library, 0.0, 0.0);
  masks.Write(forward, -1, -1, logits.data());
  EXPECT_THAT(logits, testing::ElementsAre(0.0f, 0.0f, 0.0f, kOut));
  masks.Write(forward, -1, 1, logits.data());
  EXPECT_THAT(logits, testing::ElementsAre(0.0f, 0.0f, kOut, kOut));
  // After 2 then 1, the cycle's next switch, to 0, is masked; after 0 then 1, nothing more.
  masks.Write(forward, 2, 1, logits.data());
  EXPECT_THAT(logits, testing::ElementsAre(kOut, 0.0f, kOut, kOut));
  masks.Write(forward, 0, 1, logits.data());
  EXPECT_THAT(logits, testing::ElementsAre(0.0f, 0.0f, kOut, kOut));

  SelectorPrior nearest(library, 0.1, 0.0);
  nearest.Write(forward, -1, 1, logits.data());
  std::vector<float> expected(4);
  NearestSkillSelector(library).Prior(forward, 0.1, expected.data());
  expected[2] = kOut;
  EXPECT_EQ(logits, expected);

  // The bonus goes to each hold of the time-sharing cycle (one without the barred switch).
  SelectorPrior shared(library, 0.0, 4.0);
  TimeSharingSelector time_sharing(library);
  int previous = -1, from = -1;
  for (int hold = 0; hold < 6; ++hold) {
    shared.Write(forward, previous, from, logits.data());
    const int chosen = time_sharing.Choose(forward, from);
    EXPECT_EQ(logits[chosen], 4.0f) << hold;
    EXPECT_EQ(logits[3], kOut);
    if (chosen != from) previous = from;
    from = chosen;
  }
}

TEST(MakeSelector, BuildsEachKindWithItsHoldAndRefusesALearnedOneALibraryLacks) {
  const std::string path = testutil::WriteLibrary({{0, 0, 0}, {0.5, 0, 0}}, {});
  const SkillLibrary library = SkillLibrary::Load(path);
  std::remove(path.c_str());
  EXPECT_THAT(testutil::InputErrorMessage([&] { MakeSelector(library, SelectorKind::kLearned); }),
              HasSubstr("has no skill selector"));
  EXPECT_EQ(MakeSelector(library, SelectorKind::kNearestSkill)->hold_steps(), 25);
  const std::unique_ptr<SkillSelector> shared = MakeSelector(library, SelectorKind::kTimeSharing);
  EXPECT_EQ(shared->hold_steps(), 50);
  EXPECT_EQ(shared->CommandRange()[1][0], 0.5);
  const double fast[3] = {2.0, 0.0, 0.0};
  EXPECT_EQ(shared->Clip(fast)[0], 0.5);
  SelectorMemory memory(shared->window_steps());
  const std::vector<float> still = MovingAt(0, 0, 0);
  EXPECT_EQ(shared->Choose(still.data(), fast, memory), 1);
  EXPECT_EQ(ParseSelectorKind("time_sharing"), SelectorKind::kTimeSharing);
  EXPECT_THAT(testutil::InputErrorMessage([] { ParseSelectorKind("best"); }),
              HasSubstr("expected learned or nearest_skill or time_sharing"));
}

}  // namespace
}  // namespace flsd
