#include "skills/runtime/nearest_skill.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/check.h"
#include "skills/runtime/library_format.h"

namespace flsd {
namespace {

// Survives its evaluation without falling, nominal and (where measured) randomised.
bool Dependable(const SkillDescriptor& d) {
  return !EarliestFall(d) && Survives(d.survival_steps) &&
         (!d.randomized_survival_steps || Survives(*d.randomized_survival_steps));
}

constexpr double kInPlaceSpeed = 0.05;  // m/s of travel under which a turn is in place
constexpr double kTurningRate = 0.1;    // rad/s a skill turns at least to count as a turn
constexpr double kInPlaceRadius = 0.1;  // m under which the tightest turn both ways is in place

}  // namespace

TightestTurn TightestTurnOf(const SkillLibrary& library) {
  TightestTurn side[2];  // turning right, left
  for (const SkillDescriptor& d : library.skills()) {
    const double speed = d.mean_linear_velocity.head<2>().norm(), rate = d.mean_angular_velocity.z();
    if (!Dependable(d) || std::abs(rate) < kTurningRate) continue;
    const double radius = speed < kInPlaceSpeed ? 0.0 : speed / std::abs(rate);
    TightestTurn& tightest = side[rate > 0.0];
    if (radius < tightest.radius) tightest = {radius, std::abs(rate)};
  }
  TightestTurn both{std::max(side[0].radius, side[1].radius), std::min(side[0].yaw_rate, side[1].yaw_rate)};
  if (both.radius < kInPlaceRadius) both.radius = 0.0;
  return both;
}

NearestSkillSelector::NearestSkillSelector(const SkillLibrary& library)
    : num_skills_(library.num_skills()), falling_switches_(library.falling_switches()) {
  min_.setConstant(std::numeric_limits<double>::infinity());
  max_.setConstant(-std::numeric_limits<double>::infinity());
  for (const SkillDescriptor& d : library.skills()) {
    if (!Dependable(d)) continue;
    const Eigen::Vector3d v(d.mean_linear_velocity.x(), d.mean_linear_velocity.y(), d.mean_angular_velocity.z());
    candidates_.push_back(d.id);
    velocity_.push_back(v);
    min_ = min_.cwiseMin(v);
    max_ = max_.cwiseMax(v);
  }
  if (candidates_.empty()) {
    throw InputError(library.path() + ": no skill survived " + std::to_string(kSurvivalSteps) +
                     " steps in its evaluation: the nearest-skill selector has nothing to choose from");
  }
}

std::array<double, 3> NearestSkillSelector::Clip(const double* command) const {
  std::array<double, 3> clipped;
  for (int a = 0; a < 3; ++a) clipped[a] = std::clamp(command[a], min_[a], max_[a]);
  return clipped;
}

double NearestSkillSelector::SquaredDistance(size_t i, const double* command) const {
  return SquaredDistance(velocity_[i], Eigen::Vector3d(command[0], command[1], command[2]));
}

size_t NearestSkillSelector::NearestCandidate(const double* command, int from) const {
  size_t best = 0, best_allowed = candidates_.size();
  double best_distance = std::numeric_limits<double>::infinity(), best_allowed_distance = best_distance;
  for (size_t i = 0; i < candidates_.size(); ++i) {
    const double distance = SquaredDistance(i, command);
    if (distance < best_distance) {
      best_distance = distance;
      best = i;
    }
    if (distance < best_allowed_distance && !falling_switches_.count({from, candidates_[i]})) {
      best_allowed_distance = distance;
      best_allowed = i;
    }
  }
  return best_allowed < candidates_.size() ? best_allowed : best;
}

void NearestSkillSelector::Prior(const double* command, double temperature, float* logits) const {
  std::fill(logits, logits + num_skills_, kExcludedLogit);
  for (size_t i = 0; i < candidates_.size(); ++i) {
    logits[candidates_[i]] = static_cast<float>(-SquaredDistance(i, command) / temperature);
  }
}

int TimeSharingSelector::Choose(const double* command, double seconds, int from) {
  const Eigen::Vector3d wanted(command[0], command[1], command[2]);
  if (!owed_to_ || NearestSkillSelector::Distance(wanted, *owed_to_) > kNewCommand) {
    owed_.setZero();
    owed_to_ = wanted;
  }
  // |owed + (wanted - v) seconds| is least for the v nearest wanted + owed / seconds.
  const Eigen::Vector3d target = wanted + owed_ / seconds;
  const size_t chosen = nearest_.NearestCandidate(target.data(), from);
  owed_ = (owed_ + (wanted - nearest_.velocities()[chosen]) * seconds).cwiseMax(-kMaxOwed).cwiseMin(kMaxOwed);
  return nearest_.candidates()[chosen];
}

}  // namespace flsd
