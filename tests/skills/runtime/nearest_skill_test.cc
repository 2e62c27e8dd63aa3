// The analytic selectors on a library of known descriptors. The nearest-skill one chooses the
// surviving skill nearest the command (yaw rate weighted), clips commands to what its candidates
// do, never chooses a skill that fell, and under HierarchicalPolicy holds its choice for 0.5 s. The
// time-sharing one alternates skills so that their mean velocity is the command's.

#include "skills/runtime/nearest_skill.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "skills/learning/evaluation/export.h"
#include "skills/runtime/hierarchical_policy.h"
#include "skills/runtime/safetensors.h"
#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;

struct Velocity {
  double vx, vy, wz;
};

// A library whose skill k moves at velocities[k]; skills in `fallen` fell in the randomised
// evaluation.
std::string WriteLibrary(const std::vector<Velocity>& velocities, const std::vector<int>& fallen) {
  TrainConfig config;
  config.num_skills = static_cast<int>(velocities.size());
  config.policy.actor_hidden = {8};
  config.policy.critic_hidden = {8};
  TrainedPolicy policy;
  const int obs = PolicyObservationSize(config.num_skills);
  policy.policy = ActorCritic(obs, obs + 2, kActionSize, config.policy);
  policy.normalizer = RunningNormalizer(kMotionObsSize + kActionSize);
  Evaluation nominal, randomized;
  for (int k = 0; k < config.num_skills; ++k) {
    SkillSummary s;
    s.skill = k;
    s.survival_steps = 1000;
    s.mean_linear_velocity = {velocities[k].vx, velocities[k].vy, 0.0};
    s.mean_angular_velocity = {0.0, 0.0, velocities[k].wz};
    nominal.skills.push_back(s);
    s.fell = std::find(fallen.begin(), fallen.end(), k) != fallen.end();
    randomized.skills.push_back(s);
  }
  const std::string path = testutil::UniqueTempPath("nearest.safetensors");
  WriteSkillLibrary(path, config, policy, nominal, randomized, ExportProvenance{"run", "abc", "def"});
  return path;
}

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
  for (int t = 1; t < HierarchicalPolicy::kNearestSkillHoldSteps; ++t) {
    EXPECT_EQ(policy.Act(motion.data(), stand, previous.data(), action.data()), 1) << t;
  }
  EXPECT_EQ(policy.Act(motion.data(), stand, previous.data(), action.data()), 0);
  EXPECT_EQ(ParseSelectorKind("nearest_skill"), SelectorKind::kNearestSkill);
  EXPECT_THAT(testutil::InputErrorMessage([] { ParseSelectorKind("oracle"); }),
              HasSubstr("expected learned or nearest_skill or time_sharing"));
  std::remove(path.c_str());
}

// A library that records a fall on the switch from skill 1 to skill 2 (flsd transitions --record).
std::string WriteLibraryWithAFallingSwitch(const std::vector<Velocity>& velocities) {
  const std::string path = WriteLibrary(velocities, {});
  SafeTensors file = ReadSafeTensors(path);
  nlohmann::json meta = nlohmann::json::parse(file.metadata["flsd"]);
  meta["transitions"]["falls"] = {{1, 2}};
  file.metadata["flsd"] = meta.dump();
  WriteSafeTensors(path, file);
  return path;
}

// Neither selector makes a switch the library records a fall for; from elsewhere, or from a
// stand, the same command gets the nearest skill.
TEST(NearestSkillSelector, NeverMakesASwitchTheLibraryRecordsAFallFor) {
  const std::vector<Velocity> velocities = {{0, 0, 0}, {0.5, 0, 0}, {0.8, 0, 0}, {0.7, 0.1, 0}};
  const std::string path = WriteLibraryWithAFallingSwitch(velocities);
  const SkillLibrary library = SkillLibrary::Load(path);
  const NearestSkillSelector nearest(library);
  const double fast[3] = {0.8, 0, 0};
  EXPECT_EQ(nearest.Choose(fast), 2);
  EXPECT_EQ(nearest.Choose(fast, 0), 2);
  EXPECT_EQ(nearest.Choose(fast, 1), 3);  // the next nearest
  TimeSharingSelector sharing(library);
  EXPECT_EQ(sharing.Choose(fast, 1.0, 1), 3);

  // Under HierarchicalPolicy: the skill held, or the one still running at a reset, is the one
  // switched from.
  HierarchicalPolicy policy(library, SelectorKind::kNearestSkill);
  std::vector<float> motion(kMotionObsSize, 0.0f), previous(kActionSize, 0.0f), action(kActionSize);
  const double walk[3] = {0.5, 0, 0};
  EXPECT_EQ(policy.Act(motion.data(), walk, previous.data(), action.data()), 1);
  for (int t = 1; t < HierarchicalPolicy::kNearestSkillHoldSteps; ++t) {
    policy.Act(motion.data(), fast, previous.data(), action.data());
  }
  EXPECT_EQ(policy.Act(motion.data(), fast, previous.data(), action.data()), 3);
  policy.Reset(1);
  EXPECT_EQ(policy.Act(motion.data(), fast, previous.data(), action.data()), 3);
  policy.Reset();
  EXPECT_EQ(policy.Act(motion.data(), fast, previous.data(), action.data()), 2);
  std::remove(path.c_str());
}

// The mean descriptor velocity of the skills `selector` holds for `decisions` seconds of `command`.
Eigen::Vector3d MeanOfChoices(TimeSharingSelector& selector, const Eigen::Vector3d& command, int decisions,
                              const std::vector<Velocity>& velocities, std::vector<int>* chosen = nullptr) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int n = 0; n < decisions; ++n) {
    const int skill = selector.Choose(command.data(), 1.0);
    if (chosen) chosen->push_back(skill);
    sum += Eigen::Vector3d(velocities[skill].vx, velocities[skill].vy, velocities[skill].wz);
  }
  return sum / decisions;
}

TEST(TimeSharingSelector, AlternatesSkillsSoThatTheirMeanVelocityIsTheCommand) {
  // Forward at 0.36 and 0.75 m/s, a sideways walk that drifts back, a stand, and a 0.5 m/s walk
  // that fell (never to be chosen).
  const std::vector<Velocity> velocities = {{0.36, 0, 0}, {0.75, 0, 0}, {-0.3, 0.7, 0}, {0, 0, 0}, {0.5, 0, 0}};
  const std::string path = WriteLibrary(velocities, {4});
  const SkillLibrary library = SkillLibrary::Load(path);
  TimeSharingSelector selector(library);
  std::vector<int> chosen;
  // 0.5 m/s forward: the nearest-skill selector's 0.36 m/s walk, mixed with the faster one.
  EXPECT_EQ(selector.nearest().Choose(Eigen::Vector3d(0.5, 0, 0).data()), 0);
  Eigen::Vector3d mean = MeanOfChoices(selector, {0.5, 0, 0}, 200, velocities, &chosen);
  EXPECT_NEAR(mean.x(), 0.5, 0.01);
  EXPECT_EQ(std::count(chosen.begin(), chosen.end(), 4), 0);
  EXPECT_GT(std::count(chosen.begin(), chosen.end(), 1), 40);
  // 0.5 m/s to the left: the sideways walk's drift back cancelled by walking forward.
  selector.Reset();
  mean = MeanOfChoices(selector, {0, 0.5, 0}, 200, velocities);
  EXPECT_NEAR(mean.x(), 0.0, 0.01);
  EXPECT_NEAR(mean.y(), 0.5, 0.01);
  // A command no mix of skills meets (0.8 m/s, faster than any) owes at most kMaxOwed: 100 s of it
  // owe 1 m, not 5, so 0.72 m/s (the same account) pays it back with the 0.75 m/s walk in about 40
  // s and then needs the 0.36 one; uncapped that would take 170 s.
  selector.Reset();
  MeanOfChoices(selector, {0.8, 0, 0}, 100, velocities);
  chosen.clear();
  MeanOfChoices(selector, {0.72, 0, 0}, 60, velocities, &chosen);
  EXPECT_EQ(std::count(chosen.begin(), chosen.begin() + 30, 1), 30);
  EXPECT_GT(std::count(chosen.begin() + 30, chosen.end(), 0), 0);
  // A new command starts afresh: a stand command gets the stand.
  chosen.clear();
  MeanOfChoices(selector, {0, 0, 0}, 30, velocities, &chosen);
  EXPECT_EQ(std::count(chosen.begin(), chosen.end(), 3), 30);
  // A command that wavers within kNewCommand (a path follower's) keeps one account: 0.5 and 0.55
  // m/s in turn average 0.525, where an account started afresh at each change would choose the
  // nearest skill, 0.36 m/s, every time.
  selector.Reset();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int n = 0; n < 100; ++n) {
    sum += MeanOfChoices(selector, {0.5, 0, 0}, 1, velocities) + MeanOfChoices(selector, {0.55, 0, 0}, 1, velocities);
  }
  EXPECT_NEAR(sum.x() / 200, 0.525, 0.01);
  std::remove(path.c_str());
}

TEST(TimeSharingSelector, ServesAHierarchicalPolicyThatHoldsEachChoiceASecond) {
  const std::string path = WriteLibrary({{0.36, 0, 0}, {0.75, 0, 0}}, {});
  const SkillLibrary library = SkillLibrary::Load(path);
  HierarchicalPolicy policy(library, SelectorKind::kTimeSharing);
  std::vector<float> motion(kMotionObsSize, 0.0f), previous(kActionSize, 0.0f), action(kActionSize);
  const double forward[3] = {0.5, 0, 0};
  std::vector<int> per_second;
  for (int t = 0; t < 10 * HierarchicalPolicy::kTimeSharingHoldSteps; ++t) {
    const int skill = policy.Act(motion.data(), forward, previous.data(), action.data());
    if (t % HierarchicalPolicy::kTimeSharingHoldSteps == 0) {
      per_second.push_back(skill);
    } else {
      EXPECT_EQ(skill, per_second.back()) << t;
    }
  }
  EXPECT_EQ(per_second.front(), 0);  // nothing owed yet: the nearest skill
  EXPECT_GE(std::count(per_second.begin(), per_second.end(), 1), 2);
  EXPECT_EQ(ParseSelectorKind("time_sharing"), SelectorKind::kTimeSharing);
  EXPECT_STREQ(ToString(SelectorKind::kTimeSharing), "time_sharing");
  std::remove(path.c_str());
}

}  // namespace
}  // namespace flsd
