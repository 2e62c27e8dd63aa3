#pragma once
// Cycles of holds that threw the robot when played for several periods from a stand, though none
// of their switches did when made once from a stand (`flsd cycles --record`, /cycles/falls in a
// library): a cycle's later switches start from states its first ones never reach, such as the
// speed a walk built up after a turn. A selector plays none of them.

#include <array>
#include <set>

namespace flsd {

class FallingCycles {
 public:
  // Holds per cycle, at most: the time-sharing selector's longest cycle.
  static constexpr int kMaxLength = 3;
  // A cycle's skills from its smallest rotation on, -1 past its length: a cycle entered at any of
  // its holds is the same cycle.
  using Key = std::array<int, kMaxLength>;

  // `skills`: 2 to kMaxLength skill ids in the order held, not all one skill.
  void Add(const int* skills, int length);
  // Whether the cycle of `skills` (any rotation) is recorded. No heap allocation.
  bool Contains(const int* skills, int length) const;
  // Whether a selector that held `previous` and then `running` and now chooses `next` makes the
  // switches of a recorded cycle over again: the cycle's holds with each run of one skill merged
  // (a cycle that holds a skill twice switches as one that holds it once). For a selector that
  // decides one hold at a time and cannot see a whole cycle. False if any is -1.
  bool RepeatsSwitches(int previous, int running, int next) const;

  bool empty() const { return cycles_.empty(); }
  const std::set<Key>& cycles() const { return cycles_; }

 private:
  static Key Canonical(const int* skills, int length);

  std::set<Key> cycles_;
  std::set<Key> switch_cycles_;  // each recorded cycle, runs of one skill merged
};

}  // namespace flsd
