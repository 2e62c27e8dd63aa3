#include "skills/runtime/nearest_skill.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/check.h"
#include "skills/runtime/library_format.h"

namespace flsd {
namespace {

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
    policy_.push_back(d.policy);
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
    if (distance < best_allowed_distance && !SwitchFalls(from, candidates_[i])) {
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

int TimeSharingSelector::Choose(const double* command, int from) {
  const Eigen::Vector3d wanted(command[0], command[1], command[2]);
  if (cycle_length_ == 0 || NearestSkillSelector::Distance(wanted, cycle_command_) > kNewCommand) {
    ChooseCycle(wanted, from);
  }
  const int skill = cycle_[next_];
  next_ = (next_ + 1) % cycle_length_;
  return skill;
}

void TimeSharingSelector::ChooseCycle(const Eigen::Vector3d& command, int from) {
  // The candidates nearest the command, nearest first (insertion into a fixed array: no heap).
  std::array<size_t, kCycleSkills> near;
  std::array<double, kCycleSkills> spread;  // each one's squared distance from the command
  int n = 0;
  for (size_t i = 0; i < nearest_.candidates().size(); ++i) {
    const double d = NearestSkillSelector::SquaredDistance(nearest_.velocities()[i], command);
    if (n == kCycleSkills && d >= spread[n - 1]) continue;
    int at = std::min(n, kCycleSkills - 1);
    for (; at > 0 && spread[at - 1] > d; --at) {
      near[at] = near[at - 1];
      spread[at] = spread[at - 1];
    }
    near[at] = i;
    spread[at] = d;
    n = std::min(n + 1, kCycleSkills);
  }
  const auto skill = [&](int a) { return nearest_.candidates()[near[a]]; };
  const auto velocity = [&](int a) -> const Eigen::Vector3d& { return nearest_.velocities()[near[a]]; };
  const auto policy = [&](int a) { return nearest_.policies()[near[a]]; };
  std::array<std::array<bool, kCycleSkills>, kCycleSkills> safe;  // a switch from a to b (or none)
  for (int a = 0; a < n; ++a) {
    for (int b = 0; b < n; ++b) safe[a][b] = a == b || !nearest_.SwitchFalls(skill(a), skill(b));
  }
  // Every sequence a, b, c (length 1 to 3) entered at a: its rotations are other sequences, so the
  // entry is chosen with it. Nearest first, so of equal cycles the one entered nearest wins.
  double best_cost = std::numeric_limits<double>::infinity();
  std::array<int, kMaxCycle> best{};
  int best_length = 0;
  std::array<int, kMaxCycle> seq{};
  const auto consider = [&](int length) {
    std::array<int, kMaxCycle> skills;
    for (int h = 0; h < length; ++h) skills[h] = skill(seq[h]);
    if (falling_cycles_.Contains(skills.data(), length)) return;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    double spread_sum = 0.0;
    int policy_switches = 0;
    for (int h = 0; h < length; ++h) {
      const int a = seq[h], b = seq[(h + 1) % length];
      if (!safe[a][b]) return;
      mean += velocity(a);
      spread_sum += spread[a];
      policy_switches += policy(a) != policy(b);
    }
    const double cost = NearestSkillSelector::SquaredDistance(mean / length, command) +
                        (kSpreadWeight * spread_sum + kCrossPolicyWeight * policy_switches) / length;
    if (cost < best_cost - 1e-12) {
      best_cost = cost;
      best = seq;
      best_length = length;
    }
  };
  for (seq[0] = 0; seq[0] < n; ++seq[0]) {
    if (nearest_.SwitchFalls(from, skill(seq[0]))) continue;
    consider(1);
    for (seq[1] = 0; seq[1] < n; ++seq[1]) {
      if (seq[1] == seq[0]) continue;  // a one-skill cycle, considered above
      consider(2);
      for (seq[2] = 0; seq[2] < n; ++seq[2]) consider(3);
    }
  }
  cycle_command_ = command;
  next_ = 0;
  if (best_length == 0) {  // every near skill is barred after `from`
    cycle_[0] = nearest_.Choose(command.data(), from);
    cycle_length_ = 1;
    return;
  }
  for (int h = 0; h < best_length; ++h) cycle_[h] = skill(best[h]);
  cycle_length_ = best_length;
}

}  // namespace flsd
