// A recorded cycle is found from whichever hold it is entered at, and only in its own order; a
// selector that decides one hold at a time sees it in the switches it makes.

#include "skills/runtime/falling_cycles.h"

#include <gtest/gtest.h>

#include <array>

namespace flsd {
namespace {

TEST(FallingCycles, AreFoundFromAnyHoldAndOnlyInTheirOwnOrder) {
  FallingCycles cycles;
  const int turn_walk_arc[3] = {10, 6, 3};
  cycles.Add(turn_walk_arc, 3);
  for (const auto& entered : {std::array<int, 3>{10, 6, 3}, {6, 3, 10}, {3, 10, 6}}) {
    EXPECT_TRUE(cycles.Contains(entered.data(), 3));
  }
  const int reversed[3] = {3, 6, 10}, two[2] = {10, 6};
  EXPECT_FALSE(cycles.Contains(reversed, 3));
  EXPECT_FALSE(cycles.Contains(two, 2));
  EXPECT_FALSE(cycles.Contains(two, 1));  // one skill held is no cycle
  EXPECT_EQ(cycles.cycles().size(), 1u);
  cycles.Add(reversed, 3);
  const int entered_elsewhere[3] = {6, 3, 10};
  cycles.Add(entered_elsewhere, 3);  // the first again
  EXPECT_EQ(cycles.cycles().size(), 2u);
  EXPECT_EQ(*cycles.cycles().begin(), (FallingCycles::Key{3, 6, 10}));
}

TEST(FallingCycles, ASelectorThatDecidesEachHoldSeesTheirSwitches) {
  FallingCycles cycles;
  const int turn_walk_arc[3] = {10, 6, 3};
  cycles.Add(turn_walk_arc, 3);
  EXPECT_TRUE(cycles.RepeatsSwitches(10, 6, 3));
  EXPECT_TRUE(cycles.RepeatsSwitches(3, 10, 6));
  EXPECT_FALSE(cycles.RepeatsSwitches(6, 10, 3));
  EXPECT_FALSE(cycles.RepeatsSwitches(10, 6, 10));  // back to where it came from: two switches
  EXPECT_FALSE(cycles.RepeatsSwitches(-1, 6, 3));   // from a stand
  // A sideways walk held twice to a forward walk's once switches as the two alternating.
  const int walk_twice[3] = {2, 2, 5};
  cycles.Add(walk_twice, 3);
  EXPECT_TRUE(cycles.RepeatsSwitches(2, 5, 2));
  EXPECT_TRUE(cycles.RepeatsSwitches(5, 2, 5));
  EXPECT_FALSE(cycles.RepeatsSwitches(2, 5, 7));
  const int alternating[2] = {2, 5};
  EXPECT_FALSE(cycles.Contains(alternating, 2));  // what was played is the cycle recorded
}

}  // namespace
}  // namespace flsd
