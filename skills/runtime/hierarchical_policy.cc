#include "skills/runtime/hierarchical_policy.h"

namespace flsd {

HierarchicalPolicy::HierarchicalPolicy(const SkillLibrary& library, SelectorKind kind)
    : kind_(kind),
      selector_(MakeSelector(library, kind)),
      memory_(selector_->window_steps()),
      policy_(library) {}

void HierarchicalPolicy::Reset(int running) {
  held_skill_ = -1;
  selector_->Reset();
  memory_.Reset(running);
}

int HierarchicalPolicy::Act(const float* motion_obs, const double* command, const float* previous_action,
                            float* action) {
  const std::array<double, 3> clipped = Clip(command);
  if (held_skill_ < 0 || ticks_held_ >= selector_->hold_steps()) {
    held_skill_ = selector_->Choose(motion_obs, clipped.data(), memory_);
    ticks_held_ = 0;
  }
  ++ticks_held_;
  policy_.Act(motion_obs, previous_action, held_skill_, action);
  // The velocity this step reaches is read from the next step's o^m; the one it starts from is
  // what the memory can record now.
  memory_.Record(clipped.data(), held_skill_, motion_obs);
  return held_skill_;
}

}  // namespace flsd
