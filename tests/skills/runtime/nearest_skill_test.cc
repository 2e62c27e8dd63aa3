// The analytic selectors on a library of known descriptors. The nearest-skill one chooses the
// surviving skill nearest the command (yaw rate weighted), clips commands to what its candidates
// do, never chooses a skill that fell, and under HierarchicalPolicy holds its choice for 0.5 s. The
// time-sharing one cycles through skills so that any three holds average the command, never by a
// switch the library records a fall for.

#include "skills/runtime/nearest_skill.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "skills/learning/export/compose_library.h"
#include "skills/learning/export/export.h"
#include "skills/runtime/hierarchical_policy.h"
#include "skills/runtime/safetensors.h"
#include "tests/common/test_support.h"
#include "tests/skills/runtime/test_libraries.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;

using testutil::Velocity;
using testutil::WriteLibrary;
using testutil::WriteLibraryWithFallingSwitches;

TEST(NearestSkillSelector, ChoosesTheSurvivingSkillNearestTheCommand) {
  const std::string path = WriteLibrary(
      {{0, 0, 0}, {0.5, 0, 0.1}, {-0.4, 0, 0}, {0, 0.45, 0}, {0.05, 0, 1.2}, {0, 0, -1.0}, {0.9, 0, 0}}, {6});
  const SkillLibrary library = SkillLibrary::Load(path);
  const NearestSkillSelector selector(library);
  EXPECT_EQ(selector.candidates(), (std::vector<int>{0, 1, 2, 3, 4, 5}));  // skill 6 fell
  auto choose = [&](double vx, double vy, double wz) {
    const double c[3] = {vx, vy, wz};
    return selector.Choose(c);
  };
  EXPECT_EQ(choose(0, 0, 0), 0);
  EXPECT_EQ(choose(0.5, 0, 0), 1);
  EXPECT_EQ(choose(1.0, 0, 0), 1);  // the fallen 0.9 m/s skill is never chosen
  EXPECT_EQ(choose(-0.5, 0, 0), 2);
  EXPECT_EQ(choose(0, 0.5, 0), 3);
  EXPECT_EQ(choose(0, 0, 1.0), 4);
  EXPECT_EQ(choose(0, 0, -1.0), 5);
  // Yaw rate counts half: (0.3, 0, 0.5) is nearer skill 1 (0.2 m/s and 0.4 rad/s off) than skill 0
  // (0.3 and 0.5) or skill 4 (0.25 and 0.7).
  EXPECT_EQ(choose(0.3, 0, 0.5), 1);
  const double far[3] = {2.0, -3.0, 5.0};
  const std::array<double, 3> clipped = selector.Clip(far);
  EXPECT_EQ(clipped, (std::array<double, 3>{0.5, 0.0, 1.2}));
  std::remove(path.c_str());
}

// The prior a learned selector adds to its logits: -d^2 / T for the candidates (its argmax is
// Choose's), kExcludedLogit for a skill that fell.
TEST(NearestSkillSelector, ItsPriorPeaksAtItsChoiceAndExcludesTheFallen) {
  const std::string path = WriteLibrary({{0, 0, 0}, {0.5, 0, 0.1}, {-0.4, 0, 0}, {0, 0, -1.0}, {0.9, 0, 0}}, {4});
  const SkillLibrary library = SkillLibrary::Load(path);
  const NearestSkillSelector selector(library);
  std::vector<float> prior(selector.num_skills());
  const double forward[3] = {0.5, 0, 0};
  selector.Prior(forward, 0.1, prior.data());
  EXPECT_FLOAT_EQ(prior[0], -0.25 / 0.1);
  EXPECT_FLOAT_EQ(prior[1], -(0.5 * 0.1) * (0.5 * 0.1) / 0.1);  // yaw rate weighted by kTurnWeight
  EXPECT_FLOAT_EQ(prior[2], -0.81 / 0.1);
  EXPECT_FLOAT_EQ(prior[4], NearestSkillSelector::kExcludedLogit);
  for (double vx = -1.0; vx <= 1.0; vx += 0.25) {
    for (double wz = -1.0; wz <= 1.0; wz += 0.5) {
      const double c[3] = {vx, 0.1, wz};
      selector.Prior(c, 0.3, prior.data());
      EXPECT_EQ(std::max_element(prior.begin(), prior.end()) - prior.begin(), selector.Choose(c)) << vx << " " << wz;
    }
  }
  std::remove(path.c_str());
}

TEST(NearestSkillSelector, ALibraryWithoutSurvivorsIsRefused) {
  const std::string path = WriteLibrary({{0, 0, 0}, {0.5, 0, 0}}, {0, 1});
  const SkillLibrary library = SkillLibrary::Load(path);
  EXPECT_THAT(testutil::InputErrorMessage([&] { NearestSkillSelector selector(library); }),
              HasSubstr("no skill survived 500 steps"));
  std::remove(path.c_str());
}

// Left turns of radius 0.5 (0.25 m/s at 0.5 rad/s) and 1.0, right turns of radius 0.8 (at 0.5
// rad/s) and, fallen, 0.2: the tightest turn both ways is the right one's 0.8 m, at 0.5 rad/s. A
// skill turning in place each way makes it 0; a library that turns only left has none.
TEST(TightestTurnOf, IsTheLargerOfTheTightestDependableTurnsEachWay) {
  const std::string arcs =
      WriteLibrary({{0.25, 0, 0.5}, {0.5, 0, 0.5}, {0, 0.4, -0.5}, {0.2, 0, -1.0}, {0.8, 0, 0.05}}, {3});
  const TightestTurn turn = TightestTurnOf(SkillLibrary::Load(arcs));
  EXPECT_NEAR(turn.radius, 0.8, 1e-9);
  EXPECT_NEAR(turn.yaw_rate, 0.5, 1e-9);
  const std::string in_place = WriteLibrary({{0.25, 0, 0.5}, {0.02, 0, -1.0}, {0.0, 0.01, 1.2}}, {});
  EXPECT_EQ(TightestTurnOf(SkillLibrary::Load(in_place)).radius, 0.0);
  const std::string one_way = WriteLibrary({{0.25, 0, 0.5}, {0.8, 0, -0.05}}, {});
  EXPECT_EQ(TightestTurnOf(SkillLibrary::Load(one_way)).radius, HUGE_VAL);
  EXPECT_EQ(TightestTurnOf(SkillLibrary::Load(one_way)).yaw_rate, 0.0);
  for (const std::string& path : {arcs, in_place, one_way}) std::remove(path.c_str());
}

TEST(NearestSkillSelector, ServesAHierarchicalPolicyWithoutALearnedSelectorAndHoldsItsChoice) {
  const std::string path = WriteLibrary({{0, 0, 0}, {0.5, 0, 0}}, {});
  const SkillLibrary library = SkillLibrary::Load(path);
  EXPECT_THAT(testutil::InputErrorMessage([&] { HierarchicalPolicy policy(library); }),
              HasSubstr("has no skill selector"));
  HierarchicalPolicy policy(library, SelectorKind::kNearestSkill);
  std::vector<float> motion(kMotionObsSize, 0.0f), previous(kActionSize, 0.0f), action(kActionSize);
  const double forward[3] = {0.5, 0, 0}, stand[3] = {0, 0, 0};
  EXPECT_EQ(policy.Act(motion.data(), forward, previous.data(), action.data()), 1);
  ASSERT_EQ(policy.hold_steps(), 25);  // 0.5 s
  for (int t = 1; t < policy.hold_steps(); ++t) {
    EXPECT_EQ(policy.Act(motion.data(), stand, previous.data(), action.data()), 1) << t;
  }
  EXPECT_EQ(policy.Act(motion.data(), stand, previous.data(), action.data()), 0);
  EXPECT_EQ(ParseSelectorKind("nearest_skill"), SelectorKind::kNearestSkill);
  EXPECT_THAT(testutil::InputErrorMessage([] { ParseSelectorKind("oracle"); }),
              HasSubstr("expected learned or nearest_skill or time_sharing"));
  std::remove(path.c_str());
}


// Neither selector makes a switch the library records a fall for; from elsewhere, or from a
// stand, the same command gets the nearest skill.
TEST(NearestSkillSelector, NeverMakesASwitchTheLibraryRecordsAFallFor) {
  const std::vector<Velocity> velocities = {{0, 0, 0}, {0.5, 0, 0}, {0.8, 0, 0}, {0.7, 0.1, 0}};
  const std::string path = WriteLibraryWithFallingSwitches(velocities, {{1, 2}});
  const SkillLibrary library = SkillLibrary::Load(path);
  const NearestSkillSelector nearest(library);
  const double fast[3] = {0.8, 0, 0};
  EXPECT_EQ(nearest.Choose(fast), 2);
  EXPECT_EQ(nearest.Choose(fast, 0), 2);
  EXPECT_EQ(nearest.Choose(fast, 1), 3);  // the next nearest
  TimeSharingSelector sharing(library);
  EXPECT_EQ(sharing.Choose(fast, 1), 3);

  // Under HierarchicalPolicy: the skill held, or the one still running at a reset, is the one
  // switched from.
  HierarchicalPolicy policy(library, SelectorKind::kNearestSkill);
  std::vector<float> motion(kMotionObsSize, 0.0f), previous(kActionSize, 0.0f), action(kActionSize);
  const double walk[3] = {0.5, 0, 0};
  EXPECT_EQ(policy.Act(motion.data(), walk, previous.data(), action.data()), 1);
  for (int t = 1; t < policy.hold_steps(); ++t) {
    policy.Act(motion.data(), fast, previous.data(), action.data());
  }
  EXPECT_EQ(policy.Act(motion.data(), fast, previous.data(), action.data()), 3);
  policy.Reset(1);
  EXPECT_EQ(policy.Act(motion.data(), fast, previous.data(), action.data()), 3);
  policy.Reset();
  EXPECT_EQ(policy.Act(motion.data(), fast, previous.data(), action.data()), 2);
  std::remove(path.c_str());
}

// The skills `selector` holds for `holds` holds of `command`, the first after skill `from`.
std::vector<int> Holds(TimeSharingSelector& selector, const Eigen::Vector3d& command, int holds, int from = -1) {
  std::vector<int> chosen;
  for (int n = 0; n < holds; ++n) chosen.push_back(selector.Choose(command.data(), n == 0 ? from : chosen.back()));
  return chosen;
}

// The largest distance (m/s) from `command` of the mean descriptor velocity of any three holds in
// a row: a user's 3-s window.
double WorstThreeHoldError(const std::vector<int>& holds, const std::vector<Velocity>& velocities,
                           const Eigen::Vector3d& command) {
  double worst = 0.0;
  for (size_t first = 0; first + 3 <= holds.size(); ++first) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (size_t n = first; n < first + 3; ++n) {
      const Velocity& v = velocities[holds[n]];
      mean += Eigen::Vector3d(v.vx, v.vy, v.wz) / 3.0;
    }
    worst = std::max(worst, NearestSkillSelector::Distance(mean, command));
  }
  return worst;
}

TEST(TimeSharingSelector, CyclesSkillsSoThatAnyThreeHoldsAverageTheCommand) {
  // Forward at 0.36 and 0.75 m/s, a sideways walk that drifts back, a stand, and a 0.5 m/s walk
  // that fell (never to be chosen).
  const std::vector<Velocity> velocities = {{0.36, 0, 0}, {0.75, 0, 0}, {-0.3, 0.7, 0}, {0, 0, 0}, {0.5, 0, 0}};
  const std::string path = WriteLibrary(velocities, {4});
  const SkillLibrary library = SkillLibrary::Load(path);
  TimeSharingSelector selector(library);
  // 0.5 m/s forward: the nearest-skill selector's 0.36 m/s walk twice to the 0.75 one's once (0.49).
  EXPECT_EQ(selector.nearest().Choose(Eigen::Vector3d(0.5, 0, 0).data()), 0);
  EXPECT_THAT(Holds(selector, {0.5, 0, 0}, 6), ::testing::ElementsAre(0, 1, 0, 0, 1, 0));
  // 0.5 m/s to the left: the sideways walk twice, its drift back cut by the 0.36 m/s walk, at
  // (-0.08, 0.47). With the 0.75 m/s walk the mean would be nearer, (0.05, 0.47), but each switch to
  // and from it changes the velocity by 1.26 m/s: kSpreadWeight prefers the nearer walk.
  selector.Reset();
  const std::vector<int> left = Holds(selector, {0, 0.5, 0}, 9);
  EXPECT_THAT(left, ::testing::ElementsAre(2, 0, 2, 2, 0, 2, 2, 0, 2));
  EXPECT_NEAR(WorstThreeHoldError(left, velocities, {0, 0.5, 0}), std::hypot(0.08, 0.5 - 1.4 / 3), 1e-6);
  // A command that wavers within kNewCommand (a path follower's) keeps the cycle: 0.5 and 0.55
  // m/s in turn get the 0.5 m/s cycle, not a new one at every change.
  selector.Reset();
  std::vector<int> wavering;
  for (int n = 0; n < 6; ++n) wavering.push_back(selector.Choose(Eigen::Vector3d(n % 2 ? 0.55 : 0.5, 0, 0).data()));
  EXPECT_THAT(wavering, ::testing::ElementsAre(0, 1, 0, 0, 1, 0));
  // Another command gets a new cycle at once: the stand, held.
  EXPECT_THAT(Holds(selector, {0, 0, 0}, 3, wavering.back()), ::testing::ElementsAre(3, 3, 3));
  std::remove(path.c_str());
}

// The trap a one-hold-at-a-time choice fell into on the shipped library: the sideways walk's drift
// back is best paid with the slow walk, but switching either way between them throws the robot.
// The cycle pays it with the fast walk instead, and from the slow walk enters the cycle there.
TEST(TimeSharingSelector, BuildsItsCycleOnlyOfSwitchesTheLibraryRecordsNoFallFor) {
  const std::vector<Velocity> velocities = {{0, 0, 0}, {0.41, 0, 0}, {0.8, 0, 0}, {-0.26, 0.79, 0}};
  const std::string path = WriteLibraryWithFallingSwitches(velocities, {{1, 3}, {3, 1}});
  const SkillLibrary library = SkillLibrary::Load(path);
  TimeSharingSelector selector(library);
  const Eigen::Vector3d left(0, 0.5, 0);
  const std::vector<int> from_stand = Holds(selector, left, 9);
  EXPECT_THAT(from_stand, ::testing::ElementsAre(3, 2, 3, 3, 2, 3, 3, 2, 3));
  EXPECT_LT(WorstThreeHoldError(from_stand, velocities, left), 0.1);  // (0.09, 0.53)
  selector.Reset();
  const std::vector<int> from_slow = Holds(selector, left, 9, 1);
  EXPECT_THAT(from_slow, ::testing::ElementsAre(2, 3, 3, 2, 3, 3, 2, 3, 3));
  // Without the recorded falls the slow walk pays the drift back: (-0.04, 0.53).
  const std::string free_path = WriteLibrary(velocities, {});
  const SkillLibrary free_library = SkillLibrary::Load(free_path);
  TimeSharingSelector free_selector(free_library);
  EXPECT_THAT(Holds(free_selector, left, 3), ::testing::ElementsAre(3, 1, 3));
  std::remove(path.c_str());
  std::remove(free_path.c_str());
}

// A cycle the library records a fall for when played for several periods is never played, from
// whichever hold it would be entered at: the next best cycle is.
TEST(TimeSharingSelector, NeverPlaysACycleTheLibraryRecordsAFallFor) {
  const std::vector<Velocity> velocities = {{0.36, 0, 0}, {0.75, 0, 0}, {0.3, 0, 0}, {0, 0, 0}};
  const Eigen::Vector3d walk(0.5, 0, 0);
  const std::string free_path = WriteLibraryWithFallingSwitches(velocities, {});
  const SkillLibrary free_library = SkillLibrary::Load(free_path);
  TimeSharingSelector free_selector(free_library);
  EXPECT_THAT(Holds(free_selector, walk, 6), ::testing::ElementsAre(0, 1, 0, 0, 1, 0));
  const std::string path = WriteLibraryWithFallingSwitches(velocities, {}, {{1, 0, 0}});
  const SkillLibrary library = SkillLibrary::Load(path);
  TimeSharingSelector selector(library);
  const std::vector<int> holds = Holds(selector, walk, 6);
  EXPECT_FALSE(selector.falling_cycles().Contains(selector.cycle().data(), selector.cycle_length()));
  EXPECT_THAT(holds, ::testing::Not(::testing::ElementsAre(0, 1, 0, 0, 1, 0)));
  EXPECT_LT(WorstThreeHoldError(holds, velocities, walk), 0.05);  // the slower walk in for one of 0.36
  // Avoided after a fall (as the cycle evaluation does between rounds): another cycle again.
  const auto cycle = [&] {
    return std::vector<int>(selector.cycle().begin(), selector.cycle().begin() + selector.cycle_length());
  };
  const std::vector<int> played = cycle();
  FallingCycles avoided;
  avoided.Add(played.data(), static_cast<int>(played.size()));
  selector.AvoidCycles(avoided);
  selector.Reset();
  Holds(selector, walk, 3);
  EXPECT_NE(cycle(), played);
  std::remove(path.c_str());
  std::remove(free_path.c_str());
}

// A walk of the sideways walk's own policy pays its drift back, though another policy's pays it
// back more exactly: its skills trained switching to each other (kCrossPolicyWeight).
TEST(TimeSharingSelector, PrefersACycleWithinOnePolicy) {
  const std::vector<Velocity> velocities = {{-0.26, 0.79, 0}, {0.31, 0, 0}, {0.40, 0, 0}};
  const Eigen::Vector3d left(0, 0.5, 0);
  // WriteLibrary writes one path per test: each library is moved to its own before the next.
  const auto write_as = [](const std::vector<Velocity>& v, const std::string& name) {
    const std::string path = testutil::UniqueTempPath(name);
    EXPECT_EQ(std::rename(WriteLibrary(v, {}).c_str(), path.c_str()), 0);
    return path;
  };
  const std::string one_path = write_as(velocities, "one.safetensors");
  const SkillLibrary one_policy = SkillLibrary::Load(one_path);
  TimeSharingSelector one(one_policy);
  EXPECT_THAT(Holds(one, left, 3), ::testing::ElementsAre(0, 2, 0));  // (-0.04, 0.53)
  const std::string sideways_path = write_as({velocities[0], velocities[1]}, "sideways.safetensors");
  const std::string walk_path = write_as({velocities[2]}, "walk.safetensors");
  const std::string joined_path = testutil::UniqueTempPath("joined.safetensors");
  ComposeLibraries({{sideways_path, {}}, {walk_path, {}}}, joined_path);
  const SkillLibrary two_policies = SkillLibrary::Load(joined_path);
  ASSERT_EQ(two_policies.skills()[2].policy, 1);
  TimeSharingSelector two(two_policies);
  EXPECT_THAT(Holds(two, left, 3), ::testing::ElementsAre(0, 1, 0));  // (-0.07, 0.53)
  for (const std::string& path : {one_path, sideways_path, walk_path, joined_path}) std::remove(path.c_str());
}

// With more candidates than kCycleSkills (40), the cycles are still made of the skills nearest the
// command: exactly one skill where one meets it, the two either side of it where none does.
TEST(TimeSharingSelector, MakesItsCyclesOfTheSkillsNearestTheCommand) {
  std::vector<Velocity> velocities;
  for (int k = 0; k < 40; ++k) velocities.push_back({0.05 * k - 1.0, 0, 0});  // -1.0 to 0.95 m/s
  const std::string path = WriteLibrary(velocities, {});
  const SkillLibrary library = SkillLibrary::Load(path);
  TimeSharingSelector selector(library);
  EXPECT_THAT(Holds(selector, {0.4, 0, 0}, 3), ::testing::ElementsAre(28, 28, 28));  // exactly 0.4
  selector.Reset();  // a new task: 0.425 is within kNewCommand of 0.4
  const std::vector<int> between = Holds(selector, {0.425, 0, 0}, 6);  // between 0.40 and 0.45
  EXPECT_NEAR(WorstThreeHoldError(between, velocities, {0.425, 0, 0}), 0.025 / 3, 1e-6);
  for (int skill : between) EXPECT_TRUE(skill == 28 || skill == 29) << skill;
  std::remove(path.c_str());
}

TEST(TimeSharingSelector, ServesAHierarchicalPolicyThatHoldsEachChoiceASecond) {
  const std::string path = WriteLibrary({{0.36, 0, 0}, {0.75, 0, 0}}, {});
  const SkillLibrary library = SkillLibrary::Load(path);
  HierarchicalPolicy policy(library, SelectorKind::kTimeSharing);
  std::vector<float> motion(kMotionObsSize, 0.0f), previous(kActionSize, 0.0f), action(kActionSize);
  const double forward[3] = {0.5, 0, 0};
  std::vector<int> per_second;
  ASSERT_EQ(policy.hold_steps(), 50);  // 1 s
  for (int t = 0; t < 10 * policy.hold_steps(); ++t) {
    const int skill = policy.Act(motion.data(), forward, previous.data(), action.data());
    if (t % policy.hold_steps() == 0) {
      per_second.push_back(skill);
    } else {
      EXPECT_EQ(skill, per_second.back()) << t;
    }
  }
  EXPECT_EQ(per_second.front(), 0);  // the cycle (0, 1, 0) entered at the nearest skill
  EXPECT_GE(std::count(per_second.begin(), per_second.end(), 1), 2);
  EXPECT_EQ(ParseSelectorKind("time_sharing"), SelectorKind::kTimeSharing);
  EXPECT_STREQ(ToString(SelectorKind::kTimeSharing), "time_sharing");
  std::remove(path.c_str());
}

}  // namespace
}  // namespace flsd
