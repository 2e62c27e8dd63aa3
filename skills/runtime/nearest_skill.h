#pragma once
// The analytic skill selectors, which need no training. NearestSkillSelector picks the skill whose
// measured mean velocity (its descriptor in the library) is nearest the command: the baseline any
// learned selector must beat. TimeSharingSelector alternates skills so that their velocities
// average the command (error diffusion): what skilld serves a library that ships no learned
// selector.

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <optional>
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
  int num_skills() const { return num_skills_; }
  const std::vector<int>& candidates() const { return candidates_; }
  // Each candidate's (vx, vy, wz), in the order of candidates().
  const std::vector<Eigen::Vector3d>& velocities() const { return velocity_; }
  // The range of the candidates' (vx, vy, wz), per axis.
  const Eigen::Vector3d& velocity_min() const { return min_; }
  const Eigen::Vector3d& velocity_max() const { return max_; }

 private:
  // Squared distance, yaw rate weighted, from candidate i's velocity to `command`.
  double SquaredDistance(size_t i, const double* command) const;

  int num_skills_;
  std::vector<int> candidates_;
  std::vector<Eigen::Vector3d> velocity_;  // vx, vy, wz of each candidate
  Eigen::Vector3d min_, max_;
  std::set<std::pair<int, int>> falling_switches_;  // the library's (SwitchFell)
};

// The nearest-skill selector with error diffusion (as a sigma-delta modulator): it keeps account
// of the distance it owes the command (what the skills it held fell short of it) and chooses the
// skill whose hold leaves the least owed, so that the skills it alternates between average the
// command where a single skill would miss it: 0.5 m/s forward between skills at 0.36 and 0.75, or
// a sideways walk's backward drift cancelled by a forward one. With nothing owed it is the
// nearest-skill choice. It counts on the descriptors, not the measured motion, so a skill's
// ramp-up after a switch is not wound into it.
class TimeSharingSelector {
 public:
  // What is owed is capped per axis (m, and rad for the yaw), so that a command no mix of skills
  // meets (outside their velocities' hull) does not wind it up without bound.
  static constexpr double kMaxOwed = 1.0;
  // What is owed is owed to a command: one that differs from it by more than this (m/s, the yaw
  // rate weighted as the nearest-skill distance weighs it) starts afresh.
  static constexpr double kNewCommand = 0.1;

  explicit TimeSharingSelector(const SkillLibrary& library) : nearest_(library) {}

  // The skill to hold for the next `seconds` under `command` (vx, vy, wz), as nearest_.Clip clips
  // it, after skill `from` (-1: none), never one the library records a fall for after it.
  int Choose(const double* command, double seconds, int from = -1);
  // Forgets what is owed (a new task).
  void Reset() { owed_to_.reset(); }
  const NearestSkillSelector& nearest() const { return nearest_; }

 private:
  NearestSkillSelector nearest_;
  Eigen::Vector3d owed_ = Eigen::Vector3d::Zero();  // m, m, rad
  std::optional<Eigen::Vector3d> owed_to_;         // the command it is owed to
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
