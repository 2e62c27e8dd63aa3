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
  EXPECT_DOUBLE_EQ(TravelReward(Direction::kForward, {0.5, 0.0, 0.0}, c), 2.0);
  EXPECT_DOUBLE_EQ(TravelReward(Direction::kBackward, {-0.5, 0.0, 0.0}, c), 2.0);
  EXPECT_DOUBLE_EQ(TravelReward(Direction::kLeft, {0.0, 0.5, 0.0}, c), 2.0);
  EXPECT_DOUBLE_EQ(TravelReward(Direction::kRight, {0.0, -0.5, 0.0}, c), 2.0);
  // 1.25 rad/s counts as 0.5 m/s.
  EXPECT_DOUBLE_EQ(TravelReward(Direction::kTurnLeft, {0.0, 0.0, 1.25}, c), 2.0);
  EXPECT_DOUBLE_EQ(TravelReward(Direction::kTurnRight, {0.0, 0.0, -1.25}, c), 2.0);
  // Standing is 0.5 m/s off target: exp(-0.25 / 0.25).
  EXPECT_NEAR(TravelReward(Direction::kForward, {0.0, 0.0, 0.0}, c), 2.0 * std::exp(-1.0), 1e-12);
  // Too fast costs as too slow: a gallop earns no more.
  EXPECT_DOUBLE_EQ(TravelReward(Direction::kForward, {1.0, 0.0, 0.0}, c),
                   TravelReward(Direction::kForward, {0.0, 0.0, 0.0}, c));
  // Forward on target drifting 0.3 m/s left and turning 1 rad/s (0.4 m/s): 0.25 m^2/s^2 off.
  EXPECT_NEAR(TravelReward(Direction::kForward, {0.5, 0.3, 1.0}, c), 2.0 * std::exp(-1.0), 1e-12);
  // Going the wrong way earns least, and never below zero.
  EXPECT_NEAR(TravelReward(Direction::kLeft, {0.0, -0.5, 0.0}, c), 2.0 * std::exp(-4.0), 1e-12);
}

TEST(TravelReward, IsFlatAcrossTheDirectionAboutZero) {
  // A skill exploring sideways loses next to nothing at first: the kernel's slope across is zero.
  const TravelConfig c = Pay(1.0);
  const double straight = TravelReward(Direction::kForward, {0.3, 0.0, 0.0}, c);
  EXPECT_NEAR(TravelReward(Direction::kForward, {0.3, 0.01, 0.0}, c), straight, 1e-3 * straight);
  EXPECT_GT(straight, TravelReward(Direction::kForward, {0.3, 0.0, 0.8}, c));  // straight beats an arc
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
    EXPECT_DOUBLE_EQ(TravelReward(direction, {0.3, 0.2, 0.7}, c),
                     TravelReward(MirrorImage(direction), {0.3, -0.2, -0.7}, c))
        << kDirectionNames[d];
  }
}

TEST(TravelReward, DirectionsParseByTheBarsNames) {
  TravelConfig c = Pay(1.0);
  c.directions = {"left", "none", "right", "forward"};
  const SkillDirections d = ParseSkillDirections(c, 4);
  ASSERT_EQ(d.size(), 4u);
  EXPECT_EQ(d[0], Direction::kLeft);
  EXPECT_FALSE(d[1].has_value());
  EXPECT_EQ(d[3], Direction::kForward);
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
  ExpectInputError([&] { ParseSkillDirections(c, 2); }, "travel.directions[1]: expected one of forward");
  ExpectInputError([&] { ParseSkillDirections(c, 3); }, "expected one entry per skill (3), got 2");
  // 6 skills, 2 self-paired: pairs (0, 2), (1, 3); 4 and 5 their own.
  const mirror::SkillPairing pairing(6, 2);
  c.directions = {"left", "turn_left", "right", "turn_right", "forward", "none"};
  EXPECT_NO_THROW(CheckMirrorImages(ParseSkillDirections(c, 6), pairing));
  c.directions = {"left", "turn_left", "left", "turn_right", "forward", "none"};
  ExpectInputError([&] { CheckMirrorImages(ParseSkillDirections(c, 6), pairing); },
                   "travel.directions[2]: skill 2 is skill 0's mirror image, so it must go 'right'");
  c.directions = {"left", "turn_left", "right", "turn_right", "turn_left", "none"};  // self-paired: no turn
  ExpectInputError([&] { CheckMirrorImages(ParseSkillDirections(c, 6), pairing); }, "travel.directions[4]");
}

}  // namespace
}  // namespace flsd
