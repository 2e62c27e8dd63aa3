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

namespace {

std::optional<Direction> ParseDirection(const std::string& name, size_t index) {
  if (name == "none") return std::nullopt;
  for (int d = 0; d < kNumDirections; ++d) {
    if (name == kDirectionNames[d]) return static_cast<Direction>(d);
  }
  std::string expected;
  for (const char* known : kDirectionNames) expected += std::string(known) + ", ";
  throw InputError("travel.directions[" + std::to_string(index) + "]: expected one of " + expected + "none; got '" +
                   name + "'");
}

std::string NameOf(const std::optional<Direction>& d) {
  return d ? kDirectionNames[static_cast<int>(*d)] : "none";
}

}  // namespace

SkillDirections ParseSkillDirections(const TravelConfig& config, int num_skills) {
  if (static_cast<int>(config.directions.size()) != num_skills) {
    throw InputError("travel.directions: expected one entry per skill (" + std::to_string(num_skills) + "), got " +
                     std::to_string(config.directions.size()));
  }
  SkillDirections directions;
  for (size_t k = 0; k < config.directions.size(); ++k) directions.push_back(ParseDirection(config.directions[k], k));
  return directions;
}

void CheckMirrorImages(const SkillDirections& directions, const mirror::SkillPairing& pairing) {
  FLSD_DEMAND(static_cast<int>(directions.size()) == pairing.num_skills());
  for (int k = 0; k < pairing.num_skills(); ++k) {
    const std::optional<Direction>& own = directions[k];
    const std::optional<Direction> mirrored = own ? std::optional<Direction>(MirrorImage(*own)) : std::nullopt;
    const int pair = pairing(k);
    if (directions[pair] != mirrored) {
      throw InputError("travel.directions[" + std::to_string(pair) + "]: skill " + std::to_string(pair) +
                       " is skill " + std::to_string(k) + "'s mirror image, so it must go '" + NameOf(mirrored) +
                       "' (skill " + std::to_string(k) + " goes '" + NameOf(own) + "'), got '" +
                       NameOf(directions[pair]) + "'");
    }
  }
}

double TravelReward(Direction direction, const std::array<double, 3>& v, const TravelConfig& config) {
  // The velocity and the target as three lengths per second: x, y and the turn in metres.
  const std::array<double, 3> m = {v[0], v[1], config.turn_scale * v[2]};
  std::array<double, 3> target{};
  switch (direction) {
    case Direction::kForward: target[0] = config.speed; break;
    case Direction::kBackward: target[0] = -config.speed; break;
    case Direction::kLeft: target[1] = config.speed; break;
    case Direction::kRight: target[1] = -config.speed; break;
    case Direction::kTurnLeft: target[2] = config.speed; break;
    case Direction::kTurnRight: target[2] = -config.speed; break;
  }
  double error_squared = 0.0;
  for (int a = 0; a < 3; ++a) error_squared += (m[a] - target[a]) * (m[a] - target[a]);
  return config.weight * std::exp(-error_squared / (config.tolerance * config.tolerance));
}

}  // namespace flsd
