#include "skills/runtime/falling_cycles.h"

#include "core/check.h"

namespace flsd {

FallingCycles::Key FallingCycles::Canonical(const int* skills, int length) {
  Key best;
  best.fill(-1);
  for (int start = 0; start < length; ++start) {
    Key rotation;
    rotation.fill(-1);
    for (int h = 0; h < length; ++h) rotation[h] = skills[(start + h) % length];
    if (start == 0 || rotation < best) best = rotation;
  }
  return best;
}

void FallingCycles::Add(const int* skills, int length) {
  FLSD_DEMAND(length >= 2 && length <= kMaxLength);
  // The switches: each run of one skill (cyclically) merged into one hold.
  std::array<int, kMaxLength> switches{};
  int count = 0;
  for (int h = 0; h < length; ++h) {
    if (skills[h] != skills[(h + length - 1) % length]) switches[count++] = skills[h];
  }
  FLSD_DEMAND(count >= 2);  // not one skill held throughout
  cycles_.insert(Canonical(skills, length));
  switch_cycles_.insert(Canonical(switches.data(), count));
}

bool FallingCycles::Contains(const int* skills, int length) const {
  return length >= 2 && length <= kMaxLength && cycles_.count(Canonical(skills, length)) > 0;
}

bool FallingCycles::RepeatsSwitches(int previous, int running, int next) const {
  if (previous < 0 || running < 0 || next < 0 || previous == running || running == next) return false;
  const int three[3] = {previous, running, next};
  return switch_cycles_.count(Canonical(three, next == previous ? 2 : 3)) > 0;
}

}  // namespace flsd
