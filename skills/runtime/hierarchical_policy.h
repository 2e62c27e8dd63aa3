#pragma once
// A skill library driven by velocity commands: a selector chooses the skill, the skill policy
// acts under it. The selector is the library's learned one, as the paper runs it (Sec. IV-C: the
// most probable skill for (o^m, command), chosen every decision_interval control steps and held in
// between; its logits plus the nearest-skill prior if it was trained with one), or one of the
// analytic selectors any library can use (nearest_skill.h): the nearest skill, or skills
// time-shared to average the command.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "skills/runtime/nearest_skill.h"
#include "skills/runtime/skill_library.h"

namespace flsd {

enum class SelectorKind { kLearned, kNearestSkill, kTimeSharing };
const char* ToString(SelectorKind kind);  // "learned", "nearest_skill", "time_sharing"
// Throws InputError naming the accepted names.
SelectorKind ParseSelectorKind(const std::string& name);

class HierarchicalPolicy {
 public:
  // The nearest-skill selector holds each choice this many control steps (0.5 s), so that a
  // command that wavers between two skills (a path follower's) does not switch them every tick.
  static constexpr int kNearestSkillHoldSteps = 25;
  // The time-sharing selector holds each skill 1 s: every switch costs a ramp-up, and switching
  // every 0.5 s fell in the turn-in-place commands of `flsd track`, where a longer hold did not.
  static constexpr int kTimeSharingHoldSteps = 50;

  // Throws InputError if `kind` is kLearned and the library has no selector. Holds a reference to
  // `library`, which must outlive it. No heap allocation per step.
  explicit HierarchicalPolicy(const SkillLibrary& library, SelectorKind kind = SelectorKind::kLearned);

  // `command` (vx, vy, wz) is clipped first (Clip). Writes the 12 joint actions and returns the
  // chosen skill.
  int Act(const float* motion_obs, const double* command, const float* previous_action, float* action);
  // Forgets the held skill: the next Act chooses afresh (a new task), though not a skill the library
  // records a fall for on a switch from `running` (the skill the robot still runs; -1: none).
  void Reset(int running = -1);
  // The command as the selector sees it: within the learned selector's trained ranges, or within
  // what the analytic selector's candidates do.
  std::array<double, 3> Clip(const double* command) const;
  // What Clip clips each axis (vx, vy, wz) to: lowest, then highest.
  std::array<std::array<double, 3>, 2> CommandRange() const;
  // m/s below which the learned selector zeroes a command's planar part (as in its training); 0
  // for the analytic selectors.
  double MinPlanarSpeed() const { return selector_ ? library_.selector()->min_planar_speed : 0.0; }
  SelectorKind kind() const { return kind_; }

 private:
  const SkillLibrary& library_;
  SelectorKind kind_;
  std::optional<NetworkRunner> selector_;
  // The analytic selector, or the learned one's prior.
  const NearestSkillSelector& Nearest() const { return time_sharing_ ? time_sharing_->nearest() : *nearest_; }

  std::optional<NearestSkillSelector> nearest_;  // the selector, or the learned one's prior
  std::optional<TimeSharingSelector> time_sharing_;
  PolicyRunner policy_;
  std::vector<float> task_obs_, logits_, prior_;
  int held_skill_ = -1, ticks_held_ = 0;
  int running_at_reset_ = -1;
};

}  // namespace flsd
