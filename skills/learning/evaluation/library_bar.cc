#include "skills/learning/evaluation/library_bar.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "core/check.h"

namespace flsd {
namespace {

// How fast a skill with mean body velocity (vx, vy) and yaw rate wz goes `direction` within the
// limits' other conditions; negative where it does not. A walk goes a way when it goes that way
// more than across it: a walk back at 1.2 m/s drifting 0.4 m/s right is no walk to the right.
double SpeedToward(double vx, double vy, double wz, Direction direction, const LibraryBarLimits& limits) {
  const bool straight = std::abs(wz) <= limits.straight_yaw_rate;
  const bool in_place = std::hypot(vx, vy) <= limits.turn_travel;
  auto along = [straight](double speed, double across) { return straight && speed >= std::abs(across) ? speed : -1.0; };
  switch (direction) {
    case Direction::kForward: return along(vx, vy);
    case Direction::kBackward: return along(-vx, vy);
    case Direction::kLeft: return along(vy, vx);
    case Direction::kRight: return along(-vy, vx);
    case Direction::kTurnLeft: return in_place ? wz : -1.0;
    case Direction::kTurnRight: return in_place ? -wz : -1.0;
  }
  return -1.0;
}

// How many directions have a skill (-1: none).
int DirectionsWithASkill(const std::array<int, kNumDirections>& skill) {
  return static_cast<int>(std::count_if(skill.begin(), skill.end(), [](int k) { return k >= 0; }));
}

double Threshold(Direction direction, const LibraryBarLimits& limits) {
  return direction == Direction::kTurnLeft || direction == Direction::kTurnRight ? limits.turn_rate
                                                                                  : limits.straight_speed;
}

// Offers skill `id` for every direction; each keeps the fastest that meets its threshold.
void OfferForEveryDirection(int id, double vx, double vy, double wz, const LibraryBarLimits& limits,
                            std::array<int, kNumDirections>& skill, std::array<double, kNumDirections>& speed) {
  for (int d = 0; d < kNumDirections; ++d) {
    const double s = SpeedToward(vx, vy, wz, static_cast<Direction>(d), limits);
    if (s >= Threshold(static_cast<Direction>(d), limits) && s > speed[d]) {
      skill[d] = id;
      speed[d] = s;
    }
  }
}

}  // namespace

LibraryBar JudgeLibrary(const Evaluation& evaluation, const LibraryBarLimits& limits) {
  LibraryBar bar;
  bar.num_skills = static_cast<int>(evaluation.skills.size());
  bar.skill.fill(-1);
  bar.pooled_high_frequency_ratio = evaluation.high_frequency.pooled_ratio;
  bar.lowest_mover_height = INFINITY;
  std::array<int, kNumDirections> sound_skill;  // as bar.skill, among the upright skills that do not slide
  std::array<double, kNumDirections> sound_speed{};
  sound_skill.fill(-1);
  for (const SkillSummary& s : evaluation.skills) {
    if (!Dependable(DescribeSkill(s))) continue;
    ++bar.survivors;
    OfferForEveryDirection(s.skill, s.mean_linear_velocity[0], s.mean_linear_velocity[1], s.mean_angular_velocity[2],
                           limits, bar.skill, bar.speed);
    if (s.mean_base_height >= limits.mover_height && s.mean_stance_foot_speed <= limits.mover_slip) {
      OfferForEveryDirection(s.skill, s.mean_linear_velocity[0], s.mean_linear_velocity[1],
                             s.mean_angular_velocity[2], limits, sound_skill, sound_speed);
    }
    const bool mover = std::hypot(s.mean_linear_velocity[0], s.mean_linear_velocity[1]) >= limits.mover_speed ||
                       std::abs(s.mean_angular_velocity[2]) >= limits.mover_turn_rate;
    if (!mover) continue;
    ++bar.movers;
    bar.lowest_mover_height = std::min(bar.lowest_mover_height, s.mean_base_height);
    bar.fastest_mover_slip = std::max(bar.fastest_mover_slip, s.mean_stance_foot_speed);
  }
  if (bar.movers == 0) bar.lowest_mover_height = 0.0;
  bar.directions_within_limits = DirectionsWithASkill(sound_skill);
  bar.met = bar.survivors == bar.num_skills &&
            std::none_of(bar.skill.begin(), bar.skill.end(), [](int k) { return k < 0; }) &&
            bar.lowest_mover_height >= limits.mover_height && bar.fastest_mover_slip <= limits.mover_slip &&
            bar.pooled_high_frequency_ratio <= limits.high_frequency_ratio;
  return bar;
}

bool BetterLibrary(const LibraryBar& a, const LibraryBar& b) {
  auto rank = [](const LibraryBar& bar) {
    return std::make_tuple(bar.survivors == bar.num_skills, bar.directions_within_limits, bar.survivors,
                           DirectionsWithASkill(bar.skill), -bar.fastest_mover_slip);
  };
  return rank(a) > rank(b);
}

std::array<int, kNumDirections> DirectionSkills(const SkillLibrary& library, const LibraryBarLimits& limits) {
  std::array<int, kNumDirections> skill;
  std::array<double, kNumDirections> speed{};
  skill.fill(-1);
  for (const SkillDescriptor& d : library.skills()) {
    if (!Dependable(d)) continue;
    OfferForEveryDirection(d.id, d.mean_linear_velocity.x(), d.mean_linear_velocity.y(), d.mean_angular_velocity.z(),
                           limits, skill, speed);
  }
  return skill;
}

nlohmann::json LibraryBarJson(const LibraryBar& bar) {
  nlohmann::json directions;
  for (int d = 0; d < kNumDirections; ++d) {
    directions[kDirectionNames[d]] = {{"skill", bar.skill[d] >= 0 ? nlohmann::json(bar.skill[d]) : nlohmann::json()},
                                      {"speed", bar.speed[d]}};
  }
  return {{"met", bar.met},
          {"survivors", bar.survivors},
          {"num_skills", bar.num_skills},
          {"directions", directions},
          {"directions_within_limits", bar.directions_within_limits},
          {"movers", bar.movers},
          {"lowest_mover_height", bar.lowest_mover_height},
          {"fastest_mover_slip", bar.fastest_mover_slip},
          {"pooled_high_frequency_ratio", bar.pooled_high_frequency_ratio}};
}

LibraryBar LibraryBarFromJson(const nlohmann::json& json, const std::string& where) {
  try {
    LibraryBar bar;
    bar.met = json.at("met").get<bool>();
    bar.survivors = json.at("survivors").get<int>();
    bar.num_skills = json.at("num_skills").get<int>();
    for (int d = 0; d < kNumDirections; ++d) {
      const nlohmann::json& choice = json.at("directions").at(kDirectionNames[d]);
      bar.skill[d] = choice.at("skill").is_null() ? -1 : choice.at("skill").get<int>();
      bar.speed[d] = choice.at("speed").get<double>();
    }
    bar.directions_within_limits = json.at("directions_within_limits").get<int>();
    bar.movers = json.at("movers").get<int>();
    bar.lowest_mover_height = json.at("lowest_mover_height").get<double>();
    bar.fastest_mover_slip = json.at("fastest_mover_slip").get<double>();
    bar.pooled_high_frequency_ratio = json.at("pooled_high_frequency_ratio").get<double>();
    return bar;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where + ": not a library bar as flsd eval writes it (" + e.what() + ")");
  }
}

}  // namespace flsd
