#pragma once
// What a simulated step violated of the constraints that training ends episodes by with a
// probability (Chane-Sane et al., "CaT: Constraints as Terminations for Legged Locomotion", 2024).
// Each violation is in physical units and 0 where the step kept within the limit; how likely a
// violation is to end the episode is the trainer's business (skills/learning/algorithms/constraint_terminations.h).

#include <array>

#include "core/config.h"
#include "robot/a1.h"

namespace flsd {

class Env;
struct RobotState;

enum class Constraint : int {
  kFootSlip = 0,   // m/s a stance foot slides faster than the limit
  kLowBaseMoving,  // m the base is below the limit while the robot travels or turns
  kJointSpeed,     // rad/s a joint turns faster than the limit
  kJointRange,     // rad a joint is outside its range by more than the margin
  kCalfContact,    // 1 when a calf (a knee) touched the floor
};
inline constexpr int kNumConstraints = 5;
inline constexpr std::array<const char*, kNumConstraints> kConstraintNames = {
    "foot_slip", "low_base_moving", "joint_speed", "joint_range", "calf_contact"};

struct ConstraintLimits {
  bool enabled = false;
  double slip_speed = 0.1;           // m/s, horizontal, of a foot carrying more than stance_force
  double stance_force = 20.0;        // N; CaT's foot-contact threshold for Solo, scaled to the A1's mass
  double min_moving_height = 0.24;   // m; the A1 stands at about 0.30
  double moving_speed = 0.2;         // m/s of the base in the horizontal plane: "travels"
  double moving_yaw_rate = 0.5;      // rad/s: "turns"
  double joint_speed = a1::kJointVelocityLimit;  // rad/s; skilld stops a joint past it for 0.04 s
  double joint_range_margin = 0.0;   // rad; skilld stops a joint past 0.1
  template <class V>
  void Visit(V& v) {
    v("enabled", enabled);
    v("slip_speed", slip_speed, Bounds<double>{0.0, 10.0});
    v("stance_force", stance_force, Bounds<double>{0.0, 1000.0});
    v("min_moving_height", min_moving_height, Bounds<double>{0.0, 1.0});
    v("moving_speed", moving_speed, Bounds<double>{0.0, 10.0});
    v("moving_yaw_rate", moving_yaw_rate, Bounds<double>{0.0, 100.0});
    v("joint_speed", joint_speed, Bounds<double>{0.0, 1000.0});
    v("joint_range_margin", joint_range_margin, Bounds<double>{0.0, 1.0});
  }
};

// How far the base is below min_moving_height (negative: above it). kLowBaseMoving counts it only
// while the robot travels or turns; a trainer may hold a skill to it at any speed.
double BaseHeightShortfall(const RobotState& state, const ConstraintLimits& limits);

// The violations of `env`'s last step, indexed by Constraint.
std::array<float, kNumConstraints> MeasureViolations(const Env& env, const ConstraintLimits& limits);

}  // namespace flsd
