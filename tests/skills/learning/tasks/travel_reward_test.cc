// The travel pay and its config, by hand.

#include "skills/learning/tasks/travel_reward.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "core/check.h"

namespace flsd {
namespace {

TravelConfig Pay(double weight) {
  TravelConfig c;
  c.weight = weight;
  c.speed = 0.5;
  c.turn_scale = 0.4;
  c.tolerance = 0.5;
  return c;
}

TEST(TravelReward, PaysInFullOnTargetAndLessByTheSquaredError) {
  const TravelConfig c = Pay(2.0);
  EXPECT_DOUBLE_EQ(TravelReward(TravelTarget::Going(Direction::kForward), {0.5, 0.0, 0.0}, c), 2.0);
  EXPECT_DOUBLE_EQ(TravelReward(TravelTarget::Going(Direction::kBackward), {-0.5, 0.0, 0.0}, c), 2.0);
  EXPECT_DOUBLE_EQ(TravelReward(TravelTarget::Going(Direction::kLeft), {0.0, 0.5, 0.0}, c), 2.0);
  EXPECT_DOUBLE_EQ(TravelReward(TravelTarget::Going(Direction::kRight), {0.0, -0.5, 0.0}, c), 2.0);
  // 1.25 rad/s counts as 0.5 m/s.
  EXPECT_DOUBLE_EQ(TravelReward(TravelTarget::Going(Direction::kTurnLeft), {0.0, 0.0, 1.25}, c), 2.0);
  EXPECT_DOUBLE_EQ(TravelReward(TravelTarget::Going(Direction::kTurnRight), {0.0, 0.0, -1.25}, c), 2.0);
  // Standing is 0.5 m/s off target: exp(-0.25 / 0.25).
  EXPECT_NEAR(TravelReward(TravelTarget::Going(Direction::kForward), {0.0, 0.0, 0.0}, c), 2.0 * std::exp(-1.0), 1e-12);
  // Too fast costs as too slow: a gallop earns no more.
  EXPECT_DOUBLE_EQ(TravelReward(TravelTarget::Going(Direction::kForward), {1.0, 0.0, 0.0}, c),
                   TravelReward(TravelTarget::Going(Direction::kForward), {0.0, 0.0, 0.0}, c));
  // Forward on target drifting 0.3 m/s left and turning 1 rad/s (0.4 m/s): 0.25 m^2/s^2 off.
  EXPECT_NEAR(TravelReward(TravelTarget::Going(Direction::kForward), {0.5, 0.3, 1.0}, c), 2.0 * std::exp(-1.0), 1e-12);
  // Going the wrong way earns least, and never below zero.
  EXPECT_NEAR(TravelReward(TravelTarget::Going(Direction::kLeft), {0.0, -0.5, 0.0}, c), 2.0 * std::exp(-4.0), 1e-12);
}

TEST(TravelReward, IsFlatAcrossTheDirectionAboutZero) {
  // A skill exploring sideways loses next to nothing at first: the kernel's slope across is zero.
  const TravelConfig c = Pay(1.0);
  const double straight = TravelReward(TravelTarget::Going(Direction::kForward), {0.3, 0.0, 0.0}, c);
  EXPECT_NEAR(TravelReward(TravelTarget::Going(Direction::kForward), {0.3, 0.01, 0.0}, c), straight, 1e-3 * straight);
  EXPECT_GT(straight, TravelReward(TravelTarget::Going(Direction::kForward), {0.3, 0.0, 0.8}, c));  // straight beats an arc
}

TEST(TravelReward, MirrorImagesSwapLeftAndRight) {
  EXPECT_EQ(MirrorImage(Direction::kForward), Direction::kForward);
  EXPECT_EQ(MirrorImage(Direction::kBackward), Direction::kBackward);
  EXPECT_EQ(MirrorImage(Direction::kLeft), Direction::kRight);
  EXPECT_EQ(MirrorImage(Direction::kTurnRight), Direction::kTurnLeft);
  // A skill and its mirror image earn the same from mirror-image motions (y and yaw rate negated).
  const TravelConfig c = Pay(1.0);
  for (int d = 0; d < kNumDirections; ++d) {
    const Direction direction = static_cast<Direction>(d);
    EXPECT_DOUBLE_EQ(TravelReward(TravelTarget::Going(direction), {0.3, 0.2, 0.7}, c),
                     TravelReward(TravelTarget::Going(MirrorImage(direction)), {0.3, -0.2, -0.7}, c))
        << kDirectionNames[d];
  }
}

TEST(TravelReward, StillPaysInFullAtRestAndLessForAnyMotion) {
  const TravelConfig c = Pay(2.0);
  const TravelTarget still = TravelTarget::Still();
  EXPECT_DOUBLE_EQ(TravelReward(still, {0.0, 0.0, 0.0}, c), 2.0);
  // 0.5 m/s any way, or 1.25 rad/s of turning, is one tolerance off: exp(-1).
  EXPECT_NEAR(TravelReward(still, {0.5, 0.0, 0.0}, c), 2.0 * std::exp(-1.0), 1e-12);
  EXPECT_NEAR(TravelReward(still, {0.0, -0.5, 0.0}, c), 2.0 * std::exp(-1.0), 1e-12);
  EXPECT_NEAR(TravelReward(still, {0.0, 0.0, 1.25}, c), 2.0 * std::exp(-1.0), 1e-12);
  // Its own mirror image.
  EXPECT_EQ(MirrorImage(still), still);
  EXPECT_DOUBLE_EQ(TravelReward(still, {0.1, 0.2, 0.3}, c), TravelReward(MirrorImage(still), {0.1, -0.2, -0.3}, c));
}

TEST(TravelReward, SlipShareFallsWithTheSlipPastTheConstraint) {
  TravelConfig c = Pay(2.0);
  EXPECT_DOUBLE_EQ(TravelSlipShare(0.3, c), 1.0);  // off by default
  c.slip_tolerance = 0.1;
  EXPECT_DOUBLE_EQ(TravelSlipShare(-0.05, c), 1.0);  // within the constraint
  EXPECT_DOUBLE_EQ(TravelSlipShare(0.0, c), 1.0);
  EXPECT_NEAR(TravelSlipShare(0.1, c), std::exp(-1.0), 1e-12);  // one tolerance past it
  EXPECT_NEAR(TravelSlipShare(0.2, c), std::exp(-4.0), 1e-12);
}

TEST(TravelReward, TargetsParseByTheBarsNamesAndStill) {
  TravelConfig c = Pay(1.0);
  c.directions = {"left", "none", "still", "forward"};
  const SkillTravelTargets t = ParseSkillTravelTargets(c, 4);
  ASSERT_EQ(t.size(), 4u);
  EXPECT_EQ(t[0], TravelTarget::Going(Direction::kLeft));
  EXPECT_FALSE(t[1].has_value());
  EXPECT_EQ(t[2], TravelTarget::Still());
  EXPECT_EQ(t[3], TravelTarget::Going(Direction::kForward));
  EXPECT_NE(t[2], TravelTarget::Going(Direction::kForward));
}

void ExpectInputError(const std::function<void()>& f, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(TravelReward, BadDirectionsNameTheEntry) {
  TravelConfig c = Pay(1.0);
  c.directions = {"left", "sideways"};
  ExpectInputError([&] { ParseSkillTravelTargets(c, 2); }, "travel.directions[1]: expected one of forward");
  ExpectInputError([&] { ParseSkillTravelTargets(c, 2); }, "still, none; got 'sideways'");
  ExpectInputError([&] { ParseSkillTravelTargets(c, 3); }, "expected one entry per skill (3), got 2");
  // 6 skills, 2 self-paired: pairs (0, 2), (1, 3); 4 and 5 their own.
  const mirror::SkillPairing pairing(6, 2);
  c.directions = {"left", "turn_left", "right", "turn_right", "forward", "none"};
  EXPECT_NO_THROW(CheckMirrorImages(ParseSkillTravelTargets(c, 6), pairing));
  c.directions = {"left", "turn_left", "left", "turn_right", "forward", "none"};
  ExpectInputError([&] { CheckMirrorImages(ParseSkillTravelTargets(c, 6), pairing); },
                   "travel.directions[2]: skill 2 is skill 0's mirror image, so it must go 'right'");
  c.directions = {"left", "turn_left", "right", "turn_right", "turn_left", "none"};  // self-paired: no turn
  ExpectInputError([&] { CheckMirrorImages(ParseSkillTravelTargets(c, 6), pairing); }, "travel.directions[4]");
  c.directions = {"still", "turn_left", "still", "turn_right", "still", "none"};  // still is its own image
  EXPECT_NO_THROW(CheckMirrorImages(ParseSkillTravelTargets(c, 6), pairing));
  c.directions = {"still", "turn_left", "none", "turn_right", "forward", "none"};
  ExpectInputError([&] { CheckMirrorImages(ParseSkillTravelTargets(c, 6), pairing); },
                   "skill 2 is skill 0's mirror image, so it must go 'still' (skill 0 goes 'still'), got 'none'");
}

}  // namespace
}  // namespace flsd
