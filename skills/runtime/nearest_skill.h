#pragma once
// The analytic skill selector: the skill whose measured mean velocity (its descriptor in the
// library) is nearest the command. It needs no training, so it is the baseline any learned
// selector must beat, and what skilld can serve for a library that ships no learned selector.

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <vector>

#include "skills/runtime/skill_library.h"

namespace flsd {

class NearestSkillSelector {
 public:
  // m/s that a yaw-rate difference of 1 rad/s counts as. Users (and the tracking evaluation)
  // ask for walks of 0.5 m/s and turns of 1 rad/s: with 0.5, missing either counts the same.
  static constexpr double kTurnWeight = 0.5;

  // Chooses among the skills that survived their evaluation (and the randomised one, where the
  // library records it). Throws InputError if no skill did.
  explicit NearestSkillSelector(const SkillLibrary& library);

  // The command clipped to what the candidates can do: each axis to their velocities' range.
  std::array<double, 3> Clip(const double* command) const;
  // The skill nearest `command` (vx, vy, wz), by |v_k - c| with yaw rate weighted by kTurnWeight.
  int Choose(const double* command) const;
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
