#pragma once
// The analytic skill selectors, which need no training. NearestSkillSelector picks the skill whose
// measured mean velocity (its descriptor in the library) is nearest the command: the baseline any
// learned selector must beat. TimeSharingSelector cycles through skills whose velocities average
// the command: what skilld serves a library that ships no learned selector.

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "skills/runtime/skill_library.h"

namespace flsd {

class NearestSkillSelector {
 public:
  // m/s that a yaw-rate difference of 1 rad/s counts as. Users (and the tracking evaluation)
  // ask for walks of 0.5 m/s and turns of 1 rad/s: with 0.5, missing either counts the same.
  static constexpr double kTurnWeight = 0.5;
  // |a - b|^2 for velocities (vx, vy, wz), the yaw rate weighted by kTurnWeight.
  static double SquaredDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return (a - b).cwiseProduct(Eigen::Vector3d(1.0, 1.0, kTurnWeight)).squaredNorm();
  }
  static double Distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::sqrt(SquaredDistance(a, b));
  }

  // Chooses among the skills that survived their evaluation (and the randomised one, where the
  // library records it). Throws InputError if no skill did.
  explicit NearestSkillSelector(const SkillLibrary& library);

  // The command clipped to what the candidates can do: each axis to their velocities' range.
  std::array<double, 3> Clip(const double* command) const;
  // The skill nearest `command` (vx, vy, wz), by |v_k - c| with yaw rate weighted by kTurnWeight,
  // among those the library records no fall for on a switch from skill `from` (-1: none runs;
  // SkillLibrary::SwitchFell). Should every candidate be one, the nearest of all.
  int Choose(const double* command, int from = -1) const { return candidates_[NearestCandidate(command, from)]; }
  // Its index in candidates() and velocities().
  size_t NearestCandidate(const double* command, int from = -1) const;
  // A learned selector's prior over all the library's skills (logits[num_skills()]): -d^2 /
  // temperature for a candidate at that distance from `command`, kExcludedLogit for the rest. A
  // selector that adds its network's logits to it starts as a soft nearest-skill selector (its
  // argmax is Choose's) and learns corrections to it, never a choice of an undependable skill.
  void Prior(const double* command, double temperature, float* logits) const;
  static constexpr float kExcludedLogit = -1e4f;
  // Whether the library records a fall for a switch from skill `from` (-1: none) to `to`.
  bool SwitchFalls(int from, int to) const { return falling_switches_.count({from, to}) > 0; }
  int num_skills() const { return num_skills_; }
  const std::vector<int>& candidates() const { return candidates_; }
  // Each candidate's (vx, vy, wz), in the order of candidates().
  const std::vector<Eigen::Vector3d>& velocities() const { return velocity_; }
  // Each candidate's policy (SkillDescriptor::policy), in the order of candidates().
  const std::vector<int>& policies() const { return policy_; }
  // The range of the candidates' (vx, vy, wz), per axis.
  const Eigen::Vector3d& velocity_min() const { return min_; }
  const Eigen::Vector3d& velocity_max() const { return max_; }

 private:
  // Squared distance, yaw rate weighted, from candidate i's velocity to `command`.
  double SquaredDistance(size_t i, const double* command) const;

  int num_skills_;
  std::vector<int> candidates_;
  std::vector<Eigen::Vector3d> velocity_;  // vx, vy, wz of each candidate
  std::vector<int> policy_;                // of each candidate
  Eigen::Vector3d min_, max_;
  std::set<std::pair<int, int>> falling_switches_;  // the library's (SwitchFell)
};

// Time-sharing: a cycle of skills, each held for one hold (1 s under HierarchicalPolicy), whose
// mean velocity is the command where no single skill's is: 0.5 m/s forward as walks at 0.41, 0.40
// and 0.72, or a sideways walk's backward drift paid back by a forward walk held every third hold.
// It chooses the whole cycle for a command, not one hold at a time, so that:
// - every switch in it, the one back to its start too, is one the library records no fall for,
//   and a cycle a barred switch breaks is never entered (choosing hold by hold walked into skills
//   whose way back was barred, and stood meanwhile); nor is a cycle the library records a fall
//   for when played for several periods (FallingCycles);
// - any run of whole cycles (3 s at most) averages the cycle's velocity, not just the long run.
// It counts on the descriptors, so a skill's ramp-up after a switch is not in its cost.
class TimeSharingSelector {
 public:
  // Holds per cycle, at most: 3 s of 1-s holds, the window a user judges a command over.
  static constexpr int kMaxCycle = FallingCycles::kMaxLength;
  // Cycles are made of the candidates nearest the command, this many at most, so that choosing
  // one costs the same for any library (at most 16^3 sequences, once per new command).
  static constexpr int kCycleSkills = 16;
  // A cycle of far skills (a gallop and a stand for a walk) can average a command as well as one
  // of near ones, but every switch between far skills is a long ramp-up, and a short run of them
  // swings far from the command. A cycle's cost is its mean's squared distance from the command
  // plus this weight times its skills' mean squared distance from it.
  static constexpr double kSpreadWeight = 0.05;
  // Skills of one policy trained switching between each other; a skill of another policy starts
  // from states its training never saw (a sideways walk paid back by another run's forward walk
  // drifted back 0.23 m/s in skilld, by its own run's 0.07). Each switch between policies adds this
  // weight (m^2/s^2) per hold: enough to choose a cycle within one policy where one nearly as good
  // is there.
  static constexpr double kCrossPolicyWeight = 0.005;
  // A command that differs from the cycle's by more than this (m/s, the yaw rate weighted as the
  // nearest-skill distance weighs it) gets a new cycle; one that wavers within it (a path
  // follower's, a joystick's) keeps the cycle.
  static constexpr double kNewCommand = 0.1;

  explicit TimeSharingSelector(const SkillLibrary& library)
      : nearest_(library), falling_cycles_(library.falling_cycles()) {}

  // The skill to hold next under `command` (vx, vy, wz), as nearest_.Clip clips it: the cycle's
  // next, or the first of a new cycle, entered after skill `from` (-1: none) by a switch the
  // library records no fall for. Should no cycle be enterable so, the nearest skill.
  int Choose(const double* command, int from = -1);
  // Forgets the cycle (a new task).
  void Reset() { cycle_length_ = 0; }
  // Plays none of `cycles`, in place of the library's record: the cycle evaluation measures
  // afresh, excluding only what it saw fall.
  void AvoidCycles(FallingCycles cycles) { falling_cycles_ = std::move(cycles); }
  const NearestSkillSelector& nearest() const { return nearest_; }
  // The cycles the selector never plays: the library's, or those given to AvoidCycles.
  const FallingCycles& falling_cycles() const { return falling_cycles_; }
  // The skills of the cycle chosen last, in the order held, and how many (0 before any choice).
  const std::array<int, kMaxCycle>& cycle() const { return cycle_; }
  int cycle_length() const { return cycle_length_; }

 private:
  void ChooseCycle(const Eigen::Vector3d& command, int from);

  NearestSkillSelector nearest_;
  FallingCycles falling_cycles_;
  std::array<int, kMaxCycle> cycle_{};  // skill ids
  int cycle_length_ = 0, next_ = 0;     // 0: no cycle
  Eigen::Vector3d cycle_command_ = Eigen::Vector3d::Zero();
};

// The tightest arc the library's dependable skills (those NearestSkillSelector chooses from) walk
// both ways: the larger of the tightest left and right turns' radii, each speed / |yaw rate| over
// the skills that turn at least 0.1 rad/s, and the lower of those two skills' yaw rates. radius is
// 0 if a skill turns in place each way (a radius under 0.1 m, or under 0.05 m/s of travel): such a
// library needs no turning radius. Infinite if it turns only one way, or not at all (yaw_rate 0).
struct TightestTurn {
  double radius = HUGE_VAL;  // m
  double yaw_rate = 0.0;     // rad/s
};
TightestTurn TightestTurnOf(const SkillLibrary& library);

}  // namespace flsd
