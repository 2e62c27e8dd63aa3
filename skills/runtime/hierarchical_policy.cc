#include "skills/runtime/hierarchical_policy.h"

#include <algorithm>

#include "core/check.h"
#include "robot/observation.h"

namespace flsd {
namespace {

const DenseNetwork& SelectorOf(const SkillLibrary& library) {
  if (!library.selector()) {
    throw InputError(library.path() + ": the library has no skill selector (train one with flsd train-selector, "
                     "then add it with flsd export-selector, or use the nearest-skill selector)");
  }
  return library.selector()->network;
}

}  // namespace

const char* ToString(SelectorKind kind) {
  switch (kind) {
    case SelectorKind::kLearned: return "learned";
    case SelectorKind::kNearestSkill: return "nearest_skill";
    case SelectorKind::kTimeSharing: return "time_sharing";
  }
  return "?";
}

SelectorKind ParseSelectorKind(const std::string& name) {
  for (SelectorKind kind : {SelectorKind::kLearned, SelectorKind::kNearestSkill, SelectorKind::kTimeSharing}) {
    if (name == ToString(kind)) return kind;
  }
  throw InputError("selector '" + name + "': expected learned or nearest_skill or time_sharing");
}

HierarchicalPolicy::HierarchicalPolicy(const SkillLibrary& library, SelectorKind kind)
    : library_(library),
      kind_(kind),
      policy_(library),
      task_obs_(kTaskObsSize),
      logits_(library.num_skills()) {
  if (kind == SelectorKind::kLearned) selector_.emplace(SelectorOf(library));
  if (kind == SelectorKind::kTimeSharing) {
    time_sharing_.emplace(library);
  } else if (kind == SelectorKind::kNearestSkill || library.selector()->nearest_prior_temperature > 0.0) {
    nearest_.emplace(library);
    prior_.resize(library.num_skills());
  }
}

std::array<double, 3> HierarchicalPolicy::Clip(const double* command) const {
  return selector_ ? ClipCommand(*library_.selector(), command) : Nearest().Clip(command);
}

std::array<std::array<double, 3>, 2> HierarchicalPolicy::CommandRange() const {
  if (selector_) return {library_.selector()->command_min, library_.selector()->command_max};
  const Eigen::Vector3d& lo = Nearest().velocity_min();
  const Eigen::Vector3d& hi = Nearest().velocity_max();
  return {std::array<double, 3>{lo.x(), lo.y(), lo.z()}, std::array<double, 3>{hi.x(), hi.y(), hi.z()}};
}

void HierarchicalPolicy::Reset(int running) {
  held_skill_ = -1;
  running_at_reset_ = running;
  if (time_sharing_) time_sharing_->Reset();
}

int HierarchicalPolicy::Act(const float* motion_obs, const double* command, const float* previous_action,
                            float* action) {
  const int hold = selector_       ? library_.selector()->decision_interval
                   : time_sharing_ ? kTimeSharingHoldSteps
                                   : kNearestSkillHoldSteps;
  if (held_skill_ < 0 || ticks_held_ >= hold) {
    const std::array<double, 3> clipped = Clip(command);
    const int from = held_skill_ >= 0 ? held_skill_ : running_at_reset_;
    if (selector_) {
      BuildTaskObservation(motion_obs, clipped.data(), task_obs_.data());
      selector_->Run(task_obs_.data(), logits_.data());
      if (nearest_) {
        nearest_->Prior(clipped.data(), library_.selector()->nearest_prior_temperature, prior_.data());
        for (size_t k = 0; k < logits_.size(); ++k) logits_[k] += prior_[k];
      }
      for (const auto& [a, b] : library_.falling_switches()) {
        if (a == from) logits_[b] = NearestSkillSelector::kExcludedLogit;
      }
      held_skill_ = static_cast<int>(std::max_element(logits_.begin(), logits_.end()) - logits_.begin());
    } else if (time_sharing_) {
      held_skill_ = time_sharing_->Choose(clipped.data(), from);
    } else {
      held_skill_ = nearest_->Choose(clipped.data(), from);
    }
    ticks_held_ = 0;
  }
  ++ticks_held_;
  policy_.Act(motion_obs, previous_action, held_skill_, action);
  return held_skill_;
}

}  // namespace flsd
