#pragma once
// The bar a skill library is shipped by, judged from an evaluation (flsd eval): that every skill
// survives, that some skill goes each of six ways straight, and that the movers walk upright
// without sliding or buzzing. `flsd eval` prints it for a checkpoint, so a run's kept checkpoints
// can be compared by it.

#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "skills/learning/evaluation/metrics.h"
#include "skills/runtime/skill_library.h"

namespace flsd {

struct LibraryBarLimits {
  double straight_speed = 0.4;      // m/s along the direction, at least
  double straight_yaw_rate = 0.3;   // rad/s, at most, while going straight
  double turn_rate = 1.0;           // rad/s in place, at least
  double turn_travel = 0.2;         // m/s, at most, while turning in place
  double mover_speed = 0.2;         // m/s: a skill this fast, or
  double mover_turn_rate = 0.5;     // rad/s this fast, is a mover
  double mover_height = 0.24;       // m, a mover's base at least
  double mover_slip = 0.1;          // m/s, a mover's stance feet at most
  double high_frequency_ratio = 0.05;  // pooled, at most
};

enum class Direction { kForward, kBackward, kLeft, kRight, kTurnLeft, kTurnRight };
inline constexpr int kNumDirections = 6;
inline constexpr std::array<const char*, kNumDirections> kDirectionNames = {
    "forward", "backward", "left", "right", "turn_left", "turn_right"};

struct LibraryBar {
  int survivors = 0;  // of the skills, those that ran survival_steps without falling
  int num_skills = 0;
  // The surviving skill that goes each way fastest within the limits, -1 where none does, and
  // its speed (m/s, or rad/s for the turns) that way.
  std::array<int, kNumDirections> skill{};
  std::array<double, kNumDirections> speed{};
  // Of the six directions, those that a surviving skill goes within the limits while its base stays
  // at mover_height or above and its stance feet slide at most mover_slip: a library of such skills
  // alone has these directions.
  int directions_within_limits = 0;
  int movers = 0;
  double lowest_mover_height = 0.0;  // m; 0 without movers
  double fastest_mover_slip = 0.0;   // m/s
  double pooled_high_frequency_ratio = 0.0;
  bool met = false;
};

LibraryBar JudgeLibrary(const Evaluation& evaluation, const LibraryBarLimits& limits = {});
// How a run picks the checkpoint it keeps as its best: every skill surviving first, then more
// directions within the limits, more survivors, more directions at all, less slip.
bool BetterLibrary(const LibraryBar& a, const LibraryBar& b);
// The same choice from a library's descriptors, among the skills that fell in neither of its
// evaluations (those skilld runs): per direction the skill that goes that way fastest within the
// limits, -1 where none does.
std::array<int, kNumDirections> DirectionSkills(const SkillLibrary& library, const LibraryBarLimits& limits = {});
nlohmann::json LibraryBarJson(const LibraryBar& bar);
// The inverse of LibraryBarJson; throws InputError naming `where` and the key that is missing or
// of the wrong type.
LibraryBar LibraryBarFromJson(const nlohmann::json& json, const std::string& where);

}  // namespace flsd
