#pragma once
// The one interface of the skill selectors that turn a velocity command into a skill: the
// library's learned selector, and the analytic nearest-skill and time-sharing selectors
// (nearest_skill.h) that need no training. A selector chooses at hold boundaries only; whoever runs
// it (HierarchicalPolicy, the selector's training) holds the choice for hold_steps() control steps
// and keeps its SelectorMemory. Built by MakeSelector from the library and a SelectorKind, so that
// flsd track, skilld and the benchmarks run the same selector.

#include <array>
#include <memory>
#include <optional>
#include <string>

#include "skills/runtime/nearest_skill.h"
#include "skills/runtime/selector_memory.h"
#include "skills/runtime/skill_library.h"

namespace flsd {

enum class SelectorKind { kLearned, kNearestSkill, kTimeSharing };
const char* ToString(SelectorKind kind);  // "learned", "nearest_skill", "time_sharing"
// Throws InputError naming the accepted names.
SelectorKind ParseSelectorKind(const std::string& name);

class SkillSelector {
 public:
  virtual ~SkillSelector() = default;
  // The skill to hold next: `motion_obs` is the robot's o^m now, `command` (vx, vy, wz) as Clip
  // clips it, and `memory` what was recorded since the task began (its running() skill is the one
  // the robot runs, -1 for none). Never a skill the library records a fall for on a switch from
  // the running one, unless every candidate is one.
  virtual int Choose(const float* motion_obs, const double* command, const SelectorMemory& memory) = 0;
  // A new task.
  virtual void Reset() = 0;
  // The command as the selector sees it: within the learned selector's trained ranges, or within
  // what the analytic selector's candidates do.
  virtual std::array<double, 3> Clip(const double* command) const = 0;
  // What Clip clips each axis (vx, vy, wz) to: lowest, then highest.
  virtual std::array<std::array<double, 3>, 2> CommandRange() const = 0;
  // Control steps each choice is held.
  virtual int hold_steps() const = 0;
  // Control steps of the memory's window that the selector reads (the learned one's, as trained).
  virtual int window_steps() const { return kDefaultWindowSteps; }
  // m/s below which a learned selector zeroes a command's planar part (as in its training); 0 for
  // the analytic selectors.
  virtual double min_planar_speed() const { return 0.0; }

  // 3 s: the window a user judges a command over, and the time-sharing selector's longest cycle.
  static constexpr int kDefaultWindowSteps = 150;
};

// Throws InputError if `kind` is kLearned and the library has no selector. Holds a reference to
// `library`, which must outlive it. Choose does no heap allocation.
std::unique_ptr<SkillSelector> MakeSelector(const SkillLibrary& library, SelectorKind kind);

// The selector a server config names for `library`: "learned", "nearest_skill", "time_sharing",
// or "auto", which is learned if the library has a selector and `analytic` if not. std::nullopt
// where the named one cannot run over it (learned without a selector, an analytic one without a
// dependable skill): the calls it would serve are unavailable. Throws InputError for another name.
std::optional<SelectorKind> ServedSelectorKind(const SkillLibrary& library, const std::string& name,
                                               SelectorKind analytic);

// The logits a learned selector's network's own are added to, written the same way in its training
// and in serving: NearestSkillSelector::kExcludedLogit for a skill it may not choose (one that is
// not Dependable, a switch from the running skill the library records a fall for, or one that
// makes the switches of a cycle it records a fall for over again), and the
// prior's logit for the rest: the nearest-skill prior at `nearest_temperature`, or
// `time_sharing_bonus` on the time-sharing selector's choice and 0 elsewhere, or 0 (masks only).
class SelectorPrior {
 public:
  SelectorPrior(const SkillLibrary& library, double nearest_temperature, double time_sharing_bonus);
  // A new task (the time-sharing cycle).
  void Reset() { time_sharing_.Reset(); }
  // command: (vx, vy, wz) as the selector clips it; running: the skill running, previous: the one
  // before it (SelectorMemory's; -1 for none). Writes num_skills logits.
  void Write(const double* command, int previous, int running, float* logits);

 private:
  TimeSharingSelector time_sharing_;
  double nearest_temperature_, time_sharing_bonus_;
};

}  // namespace flsd
