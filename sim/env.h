#pragma once
// One simulated A1: reset, and a 50 Hz step that runs the motor PD law at every 5 ms physics step.

#include <array>
#include <cstdint>
#include <vector>

#include "core/rng.h"
#include "robot/joint_limit_timer.h"
#include "robot/robot_state.h"
#include "robot/target_filter.h"
#include "sim/env_config.h"
#include "sim/mujoco_model.h"

namespace flsd {

// Why an episode ended. kNone while it goes on.
enum class Termination : unsigned char {
  kNone = 0,
  kTimeOut,        // reached EnvConfig::episode_steps; bootstrap, do not treat as failure
  kBodyContact,    // trunk, hip or thigh (optionally calf) touched the floor: a fall
  kTilt,           // attitude beyond TerminationConfig::max_tilt
  kLowBase,        // base below TerminationConfig::min_base_height
  kJointSpeed,     // a joint past TerminationConfig::max_joint_speed for too long
  kJointRange,     // a joint outside its range by more than TerminationConfig::joint_range_margin
  kInvalidAction,  // a NaN or infinite action; it was not applied
  kPhysics,        // MuJoCo reported an unstable simulation (bad acceleration, non-finite state)
};
const char* ToString(Termination t);
inline bool IsFailure(Termination t) { return t != Termination::kNone && t != Termination::kTimeOut; }

// The physical parameters drawn at the last reset.
struct EnvRandomization {
  double friction = 1.0;
  double restitution = 0.0;
  double base_mass_offset = 0.0;  // kg
  double link_mass_scale = 1.0;
  int action_delay = 0;  // control steps
  a1::JointArray<double> motor_strength{};
};

class Env {
 public:
  // Copies `model`, so that what is randomised stays this env's own.
  Env(const mjModel& model, const EnvConfig& config, uint64_t seed);
  Env(Env&&) = default;
  Env& operator=(Env&&) = default;
  Env(const Env&) = delete;
  Env& operator=(const Env&) = delete;

  // Draws new randomised parameters and a new initial state near the standing pose.
  void Reset();

  // Advances one control step with policy action `action` (12 floats): joint targets
  // q* = q_default + 0.25 a (after the drawn action delay, through the target filter when
  // EnvConfig::action_filter_hz is set), torque Kp (q* - q) - Kd qdot scaled by
  // the motor strength and clipped to +-33.5 N m, recomputed at each of the 4 physics steps.
  // Returns why the episode ended, or kNone. The env does not reset itself. After kPhysics,
  // state() still holds the last valid state (MuJoCo has already reset its data).
  Termination Step(const float* action);

  // Advances `substeps` physics steps (one control step by default) holding a motor-level
  // command: the server's path (stand, damp, checked policy targets) and the robot emulator's
  // (one 5 ms step at a time). Randomisation still applies.
  Termination StepCommand(const JointCommand& command, int substeps = a1::kDecimation);

  const RobotState& state() const { return state_; }
  int episode_step() const { return episode_step_; }
  // True when a calf (not the foot) touched the floor during the last step: a knee strike.
  bool calf_contact() const { return calf_contact_; }
  // The mean horizontal speed (m/s, world frame) of the feet now in contact with the floor, 0
  // when none is: how much the stance feet slide. A sim-only measure (no robot senses it),
  // computed on demand for evaluation.
  double StanceFootSpeed() const;
  // The horizontal speed (m/s, world frame) of the fastest foot pressing on the floor with more
  // than `min_force` N, 0 when none does: the stance-foot slip constraint's measure.
  double FastestStanceFoot(double min_force) const;
  const EnvRandomization& randomization() const { return randomization_; }
  const EnvConfig& config() const { return config_; }
  const mjModel& model() const { return *model_; }
  const A1ModelIndex& index() const { return index_; }

  // Direct access for tests and tools that pose the robot; call SyncState() after editing.
  mjData& data() { return *data_; }
  const mjData& data() const { return *data_; }
  void SyncState();

 private:
  double FootSpeed(int leg) const;  // m/s, horizontal, world frame
  void SampleRandomization();
  void ApplyRandomization();
  void PlaceInitialState();
  void ReadState();
  Termination CheckTermination() const;
  Termination Advance(const JointCommand& command, int substeps);

  MjModelPtr model_;
  MjDataPtr data_;
  A1ModelIndex index_;
  EnvConfig config_;
  Rng rng_;

  // Nominal values that randomisation scales, captured from the model at construction.
  std::vector<mjtNum> nominal_body_mass_;
  std::vector<mjtNum> nominal_body_inertia_;

  EnvRandomization randomization_;
  static constexpr int kHistory = RandomizationConfig::kMaxActionDelay + 1;
  std::array<std::array<float, a1::kNumJoints>, kHistory> action_history_{};
  int history_head_ = 0;
  int push_interval_steps_ = 0;
  TargetFilter target_filter_;

  RobotState state_;
  int episode_step_ = 0;
  bool body_contact_ = false;
  bool calf_contact_ = false;
  JointLimitTimer overspeed_;
};

}  // namespace flsd
