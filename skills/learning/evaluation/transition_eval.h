#pragma once
// Whether a library's skills can start from each other's motion: for every ordered pair (a, b) of
// its dependable skills (those the nearest-skill selector chooses from), skill a runs from a stand,
// then skill b takes over with no stand between, as a selector switches them. A selector can only
// use a skill from the states it can start from; a library joined from several runs has skills
// that never saw each other's states in training. Simulated without randomisation, with the
// physics the skills trained on, run as skilld runs them (PolicyRunner, Eigen). Plain C++.

#include <nlohmann/json.hpp>

#include <array>
#include <string>
#include <vector>

#include "sim/env_config.h"
#include "skills/runtime/skill_library.h"

namespace flsd {

struct TransitionResult {
  int from = -1, to = -1;  // skill ids; from -1: b started from the stand itself
  bool fell = false;       // during b (or a: then b never ran, and this counts as a fall too)
  std::array<double, 3> achieved{};  // b's mean (vx, vy, wz) after it settled, if it did not fall
};

struct TransitionEvaluation {
  double first_seconds = 0.0, second_seconds = 0.0, settle_seconds = 0.0;
  int handovers = 1;
  std::vector<int> skills;                // the dependable skills, in id order
  std::vector<TransitionResult> results;  // per target b: from the stand, then from each a != b
  int pairs = 0, falls = 0;               // over the ordered pairs (not the starts from a stand)
  std::vector<int> falls_into;            // per skill of `skills`: the pairs that fell switching to it
};

// a runs first_seconds, b second_seconds; b's velocity is averaged after settle_seconds of it.
// Whether a switch throws the robot depends on where in its stride a was: each pair is switched
// `handovers` times, a running kHandoverSpacing longer each time, and fell if any of them did
// (achieved is the first one's).
inline constexpr double kHandoverSpacing = 0.1;  // s: 5 handovers span a stride at 2 Hz
TransitionEvaluation EvaluateTransitions(const SkillLibrary& library, const EnvConfig& env, double first_seconds,
                                         double second_seconds, double settle_seconds, uint64_t seed,
                                         int handovers = 1);
nlohmann::json TransitionJson(const TransitionEvaluation& evaluation);

// Writes the library at `path` again (atomically, checked as skilld loads it) with the switches that
// fell in any of `evaluations` (run with different first_seconds: a selector that holds a skill
// 1 s switches out of it earlier than one that holds it 2 s) recorded as /transitions (the
// durations, the pairs run and the falls, [from, to]), replacing any recorded before. skilld's
// selectors then never make those switches (SkillLibrary::SwitchFell).
void RecordTransitions(const std::string& path, const std::vector<TransitionEvaluation>& evaluations);

// Whether the time-sharing selector's cycles keep the robot up when played for several periods,
// as they are: a cycle's switch can throw the robot from a state the pairwise evaluation above
// never reaches (on the shipped library, a turn, a fast walk and an arc stood two periods and fell
// on the third arc). The cycles are those the selector chooses from a stand for a grid of commands
// over its command range, `per_axis` values an axis; each is played from a stand for `periods`
// periods of 1-s holds. The library's own record of cycles is not used: a cycle that fell here is
// excluded and the grid chosen again, until a round finds no cycle not yet played (at most
// kCycleRounds), so that the grid's final choices all stood.
struct CycleResult {
  std::vector<int> skills;  // in the order held from the stand
  int commands = 0;         // grid commands the selector chose it for
  int fell_at_step = -1;    // control step of the fall, -1 if it stood
};
struct CycleEvaluation {
  int per_axis = 0, periods = 0;
  int rounds = 0;  // that played a cycle
  double hold_seconds = 0.0;
  std::vector<CycleResult> results;  // in the order played
  int falls = 0;
};
inline constexpr int kCycleRounds = 5;
CycleEvaluation EvaluateCycles(const SkillLibrary& library, const EnvConfig& env, int per_axis, int periods,
                               uint64_t seed);
nlohmann::json CycleJson(const CycleEvaluation& evaluation);
// Writes the library at `path` again (atomically, checked as skilld loads it) with the cycles that
// fell recorded as /cycles (the grid, the periods, the cycles played and the falls), replacing any
// recorded before. skilld's selectors then never play them (SkillLibrary::falling_cycles). Run it
// after `RecordTransitions`: the switches recorded change the cycles chosen.
void RecordCycles(const std::string& path, const CycleEvaluation& evaluation);

}  // namespace flsd
