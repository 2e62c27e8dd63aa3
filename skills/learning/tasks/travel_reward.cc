#include "skills/learning/tasks/travel_reward.h"

#include <cmath>

#include "core/check.h"

namespace flsd {

Direction MirrorImage(Direction direction) {
  switch (direction) {
    case Direction::kLeft: return Direction::kRight;
    case Direction::kRight: return Direction::kLeft;
    case Direction::kTurnLeft: return Direction::kTurnRight;
    case Direction::kTurnRight: return Direction::kTurnLeft;
    default: return direction;
  }
}

TravelTarget MirrorImage(const TravelTarget& target) {
  return target.still ? target : TravelTarget::Going(MirrorImage(target.direction));
}

namespace {

std::optional<TravelTarget> ParseTarget(const std::string& name, size_t index) {
  if (name == "none") return std::nullopt;
  if (name == "still") return TravelTarget::Still();
  for (int d = 0; d < kNumDirections; ++d) {
    if (name == kDirectionNames[d]) return TravelTarget::Going(static_cast<Direction>(d));
  }
  std::string expected;
  for (const char* known : kDirectionNames) expected += std::string(known) + ", ";
  throw InputError("travel.directions[" + std::to_string(index) + "]: expected one of " + expected +
                   "still, none; got '" + name + "'");
}

std::string NameOf(const std::optional<TravelTarget>& t) {
  if (!t) return "none";
  return t->still ? "still" : kDirectionNames[static_cast<int>(t->direction)];
}

}  // namespace

SkillTravelTargets ParseSkillTravelTargets(const TravelConfig& config, int num_skills) {
  if (static_cast<int>(config.directions.size()) != num_skills) {
    throw InputError("travel.directions: expected one entry per skill (" + std::to_string(num_skills) + "), got " +
                     std::to_string(config.directions.size()));
  }
  SkillTravelTargets targets;
  for (size_t k = 0; k < config.directions.size(); ++k) targets.push_back(ParseTarget(config.directions[k], k));
  return targets;
}

void CheckMirrorImages(const SkillTravelTargets& targets, const mirror::SkillPairing& pairing) {
  FLSD_DEMAND(static_cast<int>(targets.size()) == pairing.num_skills());
  for (int k = 0; k < pairing.num_skills(); ++k) {
    const std::optional<TravelTarget>& own = targets[k];
    const std::optional<TravelTarget> mirrored = own ? std::optional<TravelTarget>(MirrorImage(*own)) : std::nullopt;
    const int pair = pairing(k);
    if (targets[pair] != mirrored) {
      throw InputError("travel.directions[" + std::to_string(pair) + "]: skill " + std::to_string(pair) +
                       " is skill " + std::to_string(k) + "'s mirror image, so it must go '" + NameOf(mirrored) +
                       "' (skill " + std::to_string(k) + " goes '" + NameOf(own) + "'), got '" +
                       NameOf(targets[pair]) + "'");
    }
  }
}

double TravelReward(const TravelTarget& travel_target, const std::array<double, 3>& v, const TravelConfig& config) {
  // The velocity and the target as three lengths per second: x, y and the turn in metres.
  const std::array<double, 3> m = {v[0], v[1], config.turn_scale * v[2]};
  std::array<double, 3> target{};  // still: zero
  if (!travel_target.still) {
    switch (travel_target.direction) {
      case Direction::kForward: target[0] = config.speed; break;
      case Direction::kBackward: target[0] = -config.speed; break;
      case Direction::kLeft: target[1] = config.speed; break;
      case Direction::kRight: target[1] = -config.speed; break;
      case Direction::kTurnLeft: target[2] = config.speed; break;
      case Direction::kTurnRight: target[2] = -config.speed; break;
    }
  }
  double error_squared = 0.0;
  for (int a = 0; a < 3; ++a) error_squared += (m[a] - target[a]) * (m[a] - target[a]);
  return config.weight * std::exp(-error_squared / (config.tolerance * config.tolerance));
}

double TravelSlipShare(double slip_excess, const TravelConfig& config) {
  if (config.slip_tolerance <= 0.0 || slip_excess <= 0.0) return 1.0;
  const double x = slip_excess / config.slip_tolerance;
  return std::exp(-x * x);
}

}  // namespace flsd
