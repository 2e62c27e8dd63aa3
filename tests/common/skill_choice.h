#pragma once
// Which skills of a library a test runs: tests of the shipped library must not name skill ids,
// which change with every library shipped.

#include <algorithm>
#include <cmath>
#include <vector>

#include "skills/runtime/skill_library.h"

namespace flsd::testutil {

// The ids of the library's `n` fastest skills (planar speed) that fell in neither of its
// evaluations, fastest first; fewer when the library has fewer.
inline std::vector<int> FastestSurvivingSkills(const SkillLibrary& library, int n) {
  std::vector<const SkillDescriptor*> skills;
  for (const SkillDescriptor& d : library.skills()) {
    if (!EarliestFall(d)) skills.push_back(&d);
  }
  std::sort(skills.begin(), skills.end(), [](const SkillDescriptor* a, const SkillDescriptor* b) {
    return a->mean_linear_velocity.head<2>().norm() > b->mean_linear_velocity.head<2>().norm();
  });
  std::vector<int> ids;
  for (int k = 0; k < n && k < static_cast<int>(skills.size()); ++k) ids.push_back(skills[k]->id);
  return ids;
}

// The skill that never fell and turns fastest (either way). -1 if the library has none.
inline int FastestTurningSkill(const SkillLibrary& library) {
  int best = -1;
  for (const SkillDescriptor& d : library.skills()) {
    if (EarliestFall(d)) continue;
    if (best < 0 || std::abs(d.mean_angular_velocity.z()) > std::abs(library.skills()[best].mean_angular_velocity.z())) {
      best = d.id;
    }
  }
  return best;
}

// The calmest walk: the slowest skill that never fell and moves straight (at least 0.2 m/s, at most
// 0.1 rad/s of turning). A spinner, a gallop or a posture held at the edge of the tilt limit can
// tip past skilld's limits on the hw path when a loaded machine starves the emulator and the
// control loop (a 1.6 m/s backward gallop did so in 2 runs of 14 beside a training job).
// -1 if none.
inline int CalmestStraightSkill(const SkillLibrary& library) {
  int best = -1;
  for (const SkillDescriptor& d : library.skills()) {
    const double speed = d.mean_linear_velocity.head<2>().norm();
    if (EarliestFall(d) || speed < 0.2 || std::abs(d.mean_angular_velocity.z()) > 0.1) continue;
    if (best < 0 || speed < library.skills()[best].mean_linear_velocity.head<2>().norm()) best = d.id;
  }
  return best;
}

}  // namespace flsd::testutil
