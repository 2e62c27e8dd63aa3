#pragma once
// A skill library driven by velocity commands: a selector (selector.h) chooses the skill at hold
// boundaries, the skill policy acts under it every control step. The selector is the library's
// learned one, as it was trained, or one of the analytic selectors any library can use.

#include <array>
#include <memory>
#include <vector>

#include "skills/runtime/selector.h"
#include "skills/runtime/selector_memory.h"
#include "skills/runtime/skill_library.h"

namespace flsd {

class HierarchicalPolicy {
 public:
  // Throws InputError if `kind` is kLearned and the library has no selector. Holds a reference to
  // `library`, which must outlive it. No heap allocation per step.
  explicit HierarchicalPolicy(const SkillLibrary& library, SelectorKind kind = SelectorKind::kLearned);

  // `command` (vx, vy, wz) is clipped first (Clip). Writes the 12 joint actions and returns the
  // chosen skill.
  int Act(const float* motion_obs, const double* command, const float* previous_action, float* action);
  // A new task: the next Act chooses afresh, though not a skill the library records a fall for on
  // a switch from `running` (the skill the robot still runs; -1: none).
  void Reset(int running = -1);
  std::array<double, 3> Clip(const double* command) const { return selector_->Clip(command); }
  std::array<std::array<double, 3>, 2> CommandRange() const { return selector_->CommandRange(); }
  double MinPlanarSpeed() const { return selector_->min_planar_speed(); }
  // Control steps each choice is held.
  int hold_steps() const { return selector_->hold_steps(); }
  SelectorKind kind() const { return kind_; }

 private:
  SelectorKind kind_;
  std::unique_ptr<SkillSelector> selector_;
  SelectorMemory memory_;
  PolicyRunner policy_;
  int held_skill_ = -1, ticks_held_ = 0;
};

}  // namespace flsd
