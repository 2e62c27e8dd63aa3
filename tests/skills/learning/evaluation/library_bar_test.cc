// The shipping bar judged from known skill summaries: the fastest qualifying skill per
// direction, movers' height and slip, survival, and which failure keeps the bar unmet; and the
// same choice of direction skills from the shipped library's descriptors.

#include "skills/learning/evaluation/library_bar.h"

#include <gtest/gtest.h>

#include "core/paths.h"

namespace flsd {
namespace {

SkillSummary Skill(int id, double vx, double vy, double wz, double height = 0.28, double slip = 0.05) {
  SkillSummary s;
  s.skill = id;
  s.survival_steps = 1000;  // the whole evaluation episode
  s.mean_linear_velocity = {vx, vy, 0.0};
  s.mean_angular_velocity = {0.0, 0.0, wz};
  s.mean_base_height = height;
  s.mean_stance_foot_speed = slip;
  return s;
}

// A library that meets the bar: one skill each way, one still posture, pooled HF 0.03.
Evaluation Library() {
  Evaluation e;
  e.skills = {Skill(0, 0.5, 0.0, 0.1),  Skill(1, -0.45, 0.05, -0.2), Skill(2, 0.0, 0.42, 0.0),
              Skill(3, 0.1, -0.6, 0.25), Skill(4, 0.05, 0.0, 1.3),    Skill(5, 0.0, -0.1, -1.1),
              Skill(6, 0.0, 0.0, 0.0, 0.20, 0.3), Skill(7, 0.7, 0.0, 0.5)};
  e.high_frequency.pooled_ratio = 0.03;
  return e;
}

TEST(LibraryBar, FindsTheFastestSkillEachWayWithinTheLimits) {
  const LibraryBar bar = JudgeLibrary(Library());
  EXPECT_EQ(bar.skill, (std::array<int, kNumDirections>{0, 1, 2, 3, 4, 5}));  // 7 turns too fast
  EXPECT_DOUBLE_EQ(bar.speed[static_cast<int>(Direction::kRight)], 0.6);
  EXPECT_DOUBLE_EQ(bar.speed[static_cast<int>(Direction::kTurnRight)], 1.1);
  EXPECT_EQ(bar.movers, 7);  // the still posture's low, sliding stance does not count
  EXPECT_DOUBLE_EQ(bar.lowest_mover_height, 0.28);
  EXPECT_TRUE(bar.met);
  EXPECT_EQ(LibraryBarJson(bar)["directions"]["turn_left"]["skill"], 4);
}

TEST(LibraryBar, EachFailureKeepsItUnmet) {
  Evaluation e = Library();
  e.skills[2].mean_linear_velocity[1] = 0.39;  // no skill goes left fast enough
  LibraryBar bar = JudgeLibrary(e);
  EXPECT_EQ(bar.skill[static_cast<int>(Direction::kLeft)], -1);
  EXPECT_FALSE(bar.met);
  EXPECT_TRUE(LibraryBarJson(bar)["directions"]["left"]["skill"].is_null());

  e = Library();
  e.skills[2].mean_linear_velocity[0] = -0.45;  // more backward than left: no walk to the left
  EXPECT_EQ(JudgeLibrary(e).skill[static_cast<int>(Direction::kLeft)], -1);
  e.skills[2].mean_linear_velocity[0] = -0.41;  // more left than backward
  EXPECT_EQ(JudgeLibrary(e).skill[static_cast<int>(Direction::kLeft)], 2);

  e = Library();
  e.skills[7].mean_base_height = 0.22;  // a crouching mover
  EXPECT_FALSE(JudgeLibrary(e).met);
  e = Library();
  e.skills[4].mean_stance_foot_speed = 0.3;  // a turn that slides
  EXPECT_FALSE(JudgeLibrary(e).met);
  e = Library();
  e.skills[6].fell = true;  // the still posture falls
  bar = JudgeLibrary(e);
  EXPECT_EQ(bar.survivors, 7);
  EXPECT_FALSE(bar.met);
  e = Library();
  e.high_frequency.pooled_ratio = 0.06;
  EXPECT_FALSE(JudgeLibrary(e).met);
}

TEST(LibraryBar, CountsTheDirectionsOfUprightSkillsThatDoNotSlide) {
  Evaluation e = Library();
  EXPECT_EQ(JudgeLibrary(e).directions_within_limits, 6);
  e.skills[4].mean_stance_foot_speed = 0.3;  // the left turn slides
  e.skills[2].mean_base_height = 0.2;        // the left walk crouches
  const LibraryBar bar = JudgeLibrary(e);
  EXPECT_EQ(bar.directions_within_limits, 4);
  EXPECT_EQ(bar.skill[static_cast<int>(Direction::kTurnLeft)], 4);  // still goes that way, outside the limits
  EXPECT_EQ(LibraryBarJson(bar)["directions_within_limits"], 4);
}

TEST(LibraryBar, ABetterLibrarySurvivesFirstThenGoesMoreWays) {
  const LibraryBar whole = JudgeLibrary(Library());
  Evaluation e = Library();
  e.skills[6].fell = true;
  const LibraryBar one_falls = JudgeLibrary(e);
  EXPECT_TRUE(BetterLibrary(whole, one_falls));
  EXPECT_FALSE(BetterLibrary(one_falls, whole));
  e = Library();
  e.skills[3].mean_stance_foot_speed = 0.2;  // the right walk slides: five directions within the limits
  const LibraryBar five = JudgeLibrary(e);
  EXPECT_TRUE(BetterLibrary(whole, five));
  EXPECT_TRUE(BetterLibrary(five, one_falls));  // all surviving beats a sixth direction
  e = Library();
  e.skills[0].mean_stance_foot_speed = 0.09;  // the same directions, more slip
  EXPECT_TRUE(BetterLibrary(whole, JudgeLibrary(e)));
  EXPECT_FALSE(BetterLibrary(whole, whole));
}

// From the shipped library's descriptors: forward 6 (0.88 m/s), backward the 1.60 m/s gallop 8,
// left and right the pair 12 and 13 (0.76-0.79 m/s sideways, 0.26 back), turning left and right in
// place 10 and 11 (1.50 and 1.53 rad/s, travelling 0.11 m/s). A turn in place must travel at most
// 0.2 m/s: with 0.05, none does.
TEST(LibraryBar, DirectionSkillsOfTheShippedLibrary) {
  const SkillLibrary library = SkillLibrary::Load(ResolveDataPath("models/a1_flsd.safetensors"));
  EXPECT_EQ(DirectionSkills(library), (std::array<int, kNumDirections>{6, 8, 12, 13, 10, 11}));
  LibraryBarLimits tighter;
  tighter.turn_travel = 0.05;
  EXPECT_EQ(DirectionSkills(library, tighter)[static_cast<int>(Direction::kTurnLeft)], -1);
}

}  // namespace
}  // namespace flsd
