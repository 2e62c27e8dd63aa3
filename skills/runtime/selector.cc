#include "skills/runtime/selector.h"

#include <algorithm>
#include <vector>

#include "core/check.h"
#include "robot/observation.h"

namespace flsd {
namespace {

// A categorical policy over the library's skills (Sec. IV-C): the most probable skill for o^c (and
// its memory, for a semi-MDP selector), its logits plus the prior it was trained with.
class LearnedSelector final : public SkillSelector {
 public:
  LearnedSelector(const SkillLibrary& library, const SelectorNetwork& selector)
      : selector_(selector),
        network_(selector.network),
        prior_(library, selector.nearest_prior_temperature, selector.time_sharing_prior),
        num_skills_(library.num_skills()),
        input_(selector.inputs(num_skills_)),
        logits_(num_skills_),
        prior_logits_(num_skills_) {}

  int Choose(const float* motion_obs, const double* command, const SelectorMemory& memory) override {
    BuildTaskObservation(motion_obs, command, input_.data());
    if (selector_.memory_window_steps > 0) memory.WriteFeatures(num_skills_, input_.data() + kTaskObsSize);
    network_.Run(input_.data(), logits_.data());
    prior_.Write(command, memory.previous(), memory.running(), prior_logits_.data());
    for (int k = 0; k < num_skills_; ++k) logits_[k] += prior_logits_[k];
    return static_cast<int>(std::max_element(logits_.begin(), logits_.end()) - logits_.begin());
  }
  void Reset() override { prior_.Reset(); }
  std::array<double, 3> Clip(const double* command) const override { return ClipCommand(selector_, command); }
  std::array<std::array<double, 3>, 2> CommandRange() const override {
    return {selector_.command_min, selector_.command_max};
  }
  int hold_steps() const override { return selector_.decision_interval; }
  int window_steps() const override {
    return selector_.memory_window_steps > 0 ? selector_.memory_window_steps : kDefaultWindowSteps;
  }
  double min_planar_speed() const override { return selector_.min_planar_speed; }

 private:
  const SelectorNetwork& selector_;
  NetworkRunner network_;
  SelectorPrior prior_;
  int num_skills_;
  std::vector<float> input_, logits_, prior_logits_;
};

// The two analytic selectors share what their candidates can do.
class AnalyticSelector : public SkillSelector {
 public:
  std::array<double, 3> Clip(const double* command) const override { return nearest().Clip(command); }
  std::array<std::array<double, 3>, 2> CommandRange() const override {
    const Eigen::Vector3d& lo = nearest().velocity_min();
    const Eigen::Vector3d& hi = nearest().velocity_max();
    return {std::array<double, 3>{lo.x(), lo.y(), lo.z()}, std::array<double, 3>{hi.x(), hi.y(), hi.z()}};
  }

 protected:
  virtual const NearestSkillSelector& nearest() const = 0;
};

class NearestSkill final : public AnalyticSelector {
 public:
  // Each choice is held 0.5 s, so that a command that wavers between two skills (a path
  // follower's) does not switch them every tick.
  static constexpr int kHoldSteps = 25;

  explicit NearestSkill(const SkillLibrary& library) : nearest_(library) {}
  int Choose(const float*, const double* command, const SelectorMemory& memory) override {
    return nearest_.Choose(command, memory.running());
  }
  void Reset() override {}
  int hold_steps() const override { return kHoldSteps; }

 private:
  const NearestSkillSelector& nearest() const override { return nearest_; }
  NearestSkillSelector nearest_;
};

class TimeSharing final : public AnalyticSelector {
 public:
  // Each skill is held 1 s: every switch costs a ramp-up, and switching every 0.5 s fell in the
  // turn-in-place commands of `flsd track`, where a longer hold did not.
  static constexpr int kHoldSteps = 50;

  explicit TimeSharing(const SkillLibrary& library) : time_sharing_(library) {}
  int Choose(const float*, const double* command, const SelectorMemory& memory) override {
    return time_sharing_.Choose(command, memory.running());
  }
  void Reset() override { time_sharing_.Reset(); }
  int hold_steps() const override { return kHoldSteps; }

 private:
  const NearestSkillSelector& nearest() const override { return time_sharing_.nearest(); }
  TimeSharingSelector time_sharing_;
};

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

std::unique_ptr<SkillSelector> MakeSelector(const SkillLibrary& library, SelectorKind kind) {
  switch (kind) {
    case SelectorKind::kLearned:
      if (!library.selector()) {
        throw InputError(library.path() + ": the library has no skill selector (train one with flsd train-selector, "
                         "then add it with flsd export-selector, or use the time-sharing selector)");
      }
      return std::make_unique<LearnedSelector>(library, *library.selector());
    case SelectorKind::kNearestSkill: return std::make_unique<NearestSkill>(library);
    case SelectorKind::kTimeSharing: return std::make_unique<TimeSharing>(library);
  }
  FLSD_DEMAND(false);
}

std::optional<SelectorKind> ServedSelectorKind(const SkillLibrary& library, const std::string& name,
                                               SelectorKind analytic) {
  const SelectorKind kind = name == "auto" ? (library.selector() ? SelectorKind::kLearned : analytic)
                                           : ParseSelectorKind(name);
  const bool runs = kind == SelectorKind::kLearned
                        ? library.selector().has_value()
                        : std::any_of(library.skills().begin(), library.skills().end(),
                                      [](const SkillDescriptor& d) { return Dependable(d); });
  return runs ? std::optional<SelectorKind>(kind) : std::nullopt;
}

SelectorPrior::SelectorPrior(const SkillLibrary& library, double nearest_temperature, double time_sharing_bonus)
    : time_sharing_(library), nearest_temperature_(nearest_temperature), time_sharing_bonus_(time_sharing_bonus) {
  FLSD_DEMAND(!(nearest_temperature > 0.0 && time_sharing_bonus > 0.0));
}

void SelectorPrior::Write(const double* command, int previous, int running, float* logits) {
  const NearestSkillSelector& nearest = time_sharing_.nearest();
  if (nearest_temperature_ > 0.0) {
    nearest.Prior(command, nearest_temperature_, logits);
  } else {
    std::fill(logits, logits + nearest.num_skills(), NearestSkillSelector::kExcludedLogit);
    for (int k : nearest.candidates()) logits[k] = 0.0f;
    if (time_sharing_bonus_ > 0.0) logits[time_sharing_.Choose(command, running)] = static_cast<float>(time_sharing_bonus_);
  }
  for (int k : nearest.candidates()) {
    if (nearest.SwitchFalls(running, k) || time_sharing_.falling_cycles().RepeatsSwitches(previous, running, k)) {
      logits[k] = NearestSkillSelector::kExcludedLogit;
    }
  }
}

}  // namespace flsd
