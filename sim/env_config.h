#pragma once
// Configuration of the simulated A1 environment. Each field is read from YAML (see core/config.h);
// the defaults are legged_gym's where it has one (its A1 config), and the reason is given
// where it has none.

#include <string>

#include "core/config.h"
#include "robot/a1.h"
#include "robot/state_limits.h"
#include "robot/target_filter.h"
#include "sim/constraints.h"

namespace flsd {

// A randomised quantity: drawn uniformly from `range` at every reset when enabled.
struct RandomRange {
  bool enabled = true;
  Interval range;
  Bounds<double> allowed{0.0, 0.0};  // what a config may set `range` to; not itself configurable
  template <class V>
  void Visit(V& v) {
    v("enabled", enabled);
    v("range", range, allowed);
  }
};

struct PushConfig {
  bool enabled = true;
  double interval_s = 15.0;    // legged_gym: every 15 s
  double max_velocity = 1.0;   // m/s; base v_xy is set to U(-max, max), as in legged_gym
  template <class V>
  void Visit(V& v) {
    v("enabled", enabled);
    v("interval_s", interval_s, Bounds<double>{0.02, 3600.0});
    v("max_velocity", max_velocity, Bounds<double>{0.0, 5.0});
  }
};

// Domain randomisation of the paper's Sec. IV-A.
struct RandomizationConfig {
  static constexpr int kMaxActionDelay = 4;

  RandomRange friction{true, {0.5, 1.25}, {0.0, 5.0}};  // legged_gym's friction range
  RandomRange restitution{true, {0.0, 0.4}, {0.0, 0.95}};  // legged_gym's plane has 0
  RandomRange base_mass_offset{true, {-1.0, 1.0}, {-5.0, 5.0}};  // kg on the trunk (legged_gym)
  RandomRange link_mass_scale{true, {0.9, 1.1}, {0.1, 3.0}};  // leg links' mass and inertia, x
  // Control steps, rounded (1 step = 20 ms): the A1's UDP round trip and estimator add about one.
  RandomRange action_delay{true, {0.0, 1.0}, {0.0, kMaxActionDelay}};
  RandomRange motor_strength{true, {0.9, 1.1}, {0.1, 2.0}};  // per joint, scales the PD torque
  PushConfig push;

  template <class V>
  void Visit(V& v) {
    v("friction", friction);
    v("restitution", restitution);
    v("base_mass_offset", base_mass_offset);
    v("link_mass_scale", link_mass_scale);
    v("action_delay", action_delay);
    v("motor_strength", motor_strength);
    v("push", push);
  }
  // Turns every randomisation off: the nominal robot on the nominal floor.
  void DisableAll() {
    for (RandomRange* r : {&friction, &restitution, &base_mass_offset, &link_mass_scale,
                           &action_delay, &motor_strength}) {
      r->enabled = false;
    }
    push.enabled = false;
  }
};

struct ResetConfig {
  Interval joint_pos_scale{0.5, 1.5};  // q = q_default * U(range), clipped to the joint range
  double base_velocity = 0.5;          // each of the 6 base velocities ~ U(-x, x) (legged_gym)
  double foot_clearance = 0.005;       // m between the lowest foot and the floor at reset
  // The share of resets that start as skilld starts a skill: the default pose, at rest. Skills
  // trained only from legged_gym's scattered starts made a third of their speed from a stand.
  double standing_fraction = 0.0;
  template <class V>
  void Visit(V& v) {
    v("joint_pos_scale", joint_pos_scale, Bounds<double>{0.0, 3.0});
    v("base_velocity", base_velocity, Bounds<double>{0.0, 5.0});
    v("foot_clearance", foot_clearance, Bounds<double>{0.0, 0.5});
    v("standing_fraction", standing_fraction, Bounds<double>{0.0, 1.0});
  }
};

struct TerminationConfig {
  // A fall: any trunk, hip or thigh geom touching the floor (legged_gym ends on base contact;
  // we add thighs). Calf contact is a knee strike and counted, but does not end it.
  bool on_calf_contact = false;
  // The state limits skilld's supervisor stops the robot by (robot/state_limits.h), here with
  // training's defaults: a tilt of 1.2 rad; a base at 0.08 m (the paper's skills reach 0.09 m,
  // Table I); no joint range (MuJoCo's joint limits are soft; skilld stops the robot at 0.1 rad
  // past them) and no joint speed. Set to the motor's 21 rad/s with the default time, the speed
  // ends an episode exactly where skilld would stop the robot; with a time of 0, the first sample
  // past 21 rad/s, it led FLSD to still postures on our budget (runs/flsd_limit_s1,
  // runs/flsd_s2_limit). configs/flsd_cpu_served.yaml sets skilld's limits.
  StateLimits limits{1.2, 0.08, -1.0, 0.0, a1::kJointOverspeedTolerance};
  template <class V>
  void Visit(V& v) {
    v("on_calf_contact", on_calf_contact);
    v("max_tilt", limits.max_tilt, Bounds<double>{0.1, 3.2});
    v("min_base_height", limits.min_base_height, Bounds<double>{0.0, 1.0});
    v("max_joint_speed", limits.max_joint_speed, Bounds<double>{0.0, 1000.0});
    v("max_joint_speed_time", limits.max_joint_speed_time, Bounds<double>{0.0, 10.0});
    v("joint_range_margin", limits.joint_range_margin, Bounds<double>{-1.0, 1.0});
  }
};

struct EnvConfig {
  std::string model = "robot/a1/scene.xml";
  int episode_steps = 1000;  // 20 s at 50 Hz, as legged_gym
  // The motors' torque-speed line (robot/robot_state.h, DrivingTorqueLimit): without it the
  // simulated joints reached 24-56 rad/s in training, past what the A1's motors can turn and what
  // skilld's supervisor allows. Runs trained before it existed had it off.
  bool torque_speed_limit = true;
  // rad/s up to which the motors keep their full torque on that line; 0 is a line falling from
  // rest, which leaves 18 N m of 33.5 at a stepping leg's 9.5 rad/s. a1::kTorqueSpeedKnee is
  // Unitree's motor shape (configs/flsd_cpu_symmetric.yaml). 0 by default: the shipped library
  // trained with the line, and skilld's simulated A1 must be the one its skills were trained on.
  double torque_speed_knee = 0.0;
  // Order of the target filter below: 1 (exponential) or 2 (Butterworth).
  int action_filter_order = 1;
  // Hz; 0 is off. The cutoff of the low-pass filter between a policy's joint targets and the
  // motors (robot/target_filter.h). A skill library records it and skilld runs the same filter.
  double action_filter_hz = 0.0;
  ResetConfig reset;
  TerminationConfig termination;
  ConstraintLimits constraints;  // measured by VecEnv when enabled
  RandomizationConfig randomization;
  template <class V>
  void Visit(V& v) {
    v("model", model);
    v("episode_steps", episode_steps, Bounds<int>{1, 10000000});
    v("torque_speed_limit", torque_speed_limit);
    v("torque_speed_knee", torque_speed_knee, Bounds<double>{0.0, a1::kJointVelocityLimit - 1.0});
    v("action_filter_order", action_filter_order, Bounds<int>{1, 2});
    v("action_filter_hz", action_filter_hz, Bounds<double>{0.0, TargetFilter::kMaxCutoffHz});
    v("reset", reset);
    v("termination", termination);
    v("constraints", constraints);
    v("randomization", randomization);
  }
};

}  // namespace flsd
