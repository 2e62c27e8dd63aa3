#pragma once
// How well a library's selector (learned or nearest-skill) and skills track velocity commands:
// each of a fixed set of commands held for some seconds on the simulated A1 without randomisation,
// from a stand, run exactly as skilld runs it (HierarchicalPolicy, Eigen). Plain C++: no libtorch.

#include <nlohmann/json.hpp>

#include <array>
#include <string>
#include <vector>

#include "sim/env_config.h"
#include "skills/runtime/hierarchical_policy.h"

namespace flsd {

struct TrackingCase {
  std::string name;
  std::array<double, 3> command;  // vx, vy (m/s), wz (rad/s), body frame
};
// Stand, forward, backward, left, right, turn left, turn right, forward while turning.
std::vector<TrackingCase> StandardTrackingCases();
// The fixed evaluation set a selector is judged on: the eight standard commands, then
// kDrawnTrackingCases drawn once from kTrackingCaseSeed, each axis uniform over the range of the
// library's dependable skills' velocities with 0 in it ("drawn_00", ...). Fixed before any
// selector was trained against it; the same library gives the same set on every machine.
inline constexpr int kDrawnTrackingCases = 32;
inline constexpr uint64_t kTrackingCaseSeed = 20261206;
// The simulator's seed of every evaluation on the set (its starts' small joint offsets): a fall
// can hang on it, so every tool that reports on the set uses this one.
inline constexpr uint64_t kTrackingEnvSeed = 1;
std::vector<TrackingCase> EvaluationTrackingCases(const SkillLibrary& library);

// How far an achieved mean velocity (vx, vy, wz) is from the command: |error| in xy (m/s), and in
// wz (rad/s). Against what was asked: a selector that clips a command it cannot follow still misses it.
struct TrackingError {
  double lin = 0.0, ang = 0.0;
};
TrackingError TrackingErrorOf(const std::array<double, 3>& achieved, const std::array<double, 3>& command);

struct TrackingResult {
  TrackingCase tracked;                  // the command after clipping to the trained ranges
  std::array<double, 3> achieved{};      // mean body velocity after the settling time
  double lin_error = 0.0, ang_error = 0.0;  // |achieved - asked| in xy, and in wz (before clipping)
  int steps = 0;                         // control steps run (fewer than asked if it fell)
  bool fell = false;
  int skills_used = 0;                   // distinct skills the selector chose
  double switches_per_s = 0.0;           // how often the chosen skill changed
  // Each run of one skill: {skill (-1: a joint-level policy), its first control step}, in order;
  // what a fall followed.
  std::vector<std::array<int, 2>> holds;
};

struct TrackingEvaluation {
  SelectorKind selector = SelectorKind::kLearned;
  double seconds = 0.0, settle_seconds = 0.0;
  std::vector<TrackingResult> cases;
  double rms_lin_error = 0.0, rms_ang_error = 0.0;  // over the cases
  int falls = 0;
  double switches_per_s = 0.0;  // the cases' mean
};

// What runs the robot through a tracking case: a library's skills under a selector, or a
// joint-level policy (the velocity task's Scratch).
class TrackingController {
 public:
  virtual ~TrackingController() = default;
  // A new case, from a stand.
  virtual void Reset() = 0;
  // The command as the controller follows it (errors are against the command as asked).
  virtual std::array<double, 3> Clip(const double* command) const = 0;
  // Writes the 12 joint actions; returns the skill that acted (-1: none).
  virtual int Act(const float* motion_obs, const double* command, const float* previous_action, float* action) = 0;
};

// Each case with `controller` on `served` (as ServedEnvConfig makes it; episode_steps is set here).
TrackingEvaluation EvaluateController(TrackingController& controller, const EnvConfig& served,
                                      const std::vector<TrackingCase>& cases, double seconds, double settle_seconds,
                                      uint64_t seed);

// Each case from a stand for `seconds`, the achieved velocity averaged after `settle_seconds`.
// Throws InputError if `selector` is kLearned and the library has none.
TrackingEvaluation EvaluateTracking(const SkillLibrary& library, const EnvConfig& env,
                                    const std::vector<TrackingCase>& cases, double seconds, double settle_seconds,
                                    uint64_t seed, SelectorKind selector = SelectorKind::kLearned);
nlohmann::json TrackingJson(const TrackingEvaluation& evaluation);

// The simulated A1 a library's skills were trained on (its metadata's training config), for
// evaluating them as they were trained.
EnvConfig TrainingEnvOf(const SkillLibrary& library);
// `env` as skilld's simulated A1 runs the library: no randomisation, every start from a stand,
// the library's target filter, and episodes of `steps` control steps.
EnvConfig ServedEnvConfig(const SkillLibrary& library, const EnvConfig& env, int steps);
// The same without a library: the target filter `env` has (a joint-level policy's).
EnvConfig ServedEnvConfig(const EnvConfig& env, int steps);

// `flsd track`: `cases` with the library's learned selector (where it has one) and with the
// nearest-skill and time-sharing selectors, side by side.
nlohmann::json CompareSelectors(const SkillLibrary& library, const std::vector<TrackingCase>& cases, double seconds,
                                double settle_seconds, uint64_t seed);

}  // namespace flsd
