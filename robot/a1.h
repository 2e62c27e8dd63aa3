#pragma once
// The Unitree A1 as both halves of FLSD see it: joint order, limits, the default standing pose
// and the low-level control convention. This is the one source of truth; robot/a1/a1.urdf and
// robot/a1/a1.xml are checked against it by tests/robot/a1_model_test.cc.

#include <array>

namespace flsd::a1 {

inline constexpr int kNumLegs = 4;
inline constexpr int kJointsPerLeg = 3;
inline constexpr int kNumJoints = kNumLegs * kJointsPerLeg;

template <class T>
using JointArray = std::array<T, kNumJoints>;

// Leg order FR, FL, RR, RL; within a leg hip (abduction, about x), thigh and calf (about y).
inline constexpr std::array<const char*, kNumLegs> kLegNames = {"FR", "FL", "RR", "RL"};
inline constexpr JointArray<const char*> kJointNames = {
    "FR_hip_joint", "FR_thigh_joint", "FR_calf_joint",  //
    "FL_hip_joint", "FL_thigh_joint", "FL_calf_joint",  //
    "RR_hip_joint", "RR_thigh_joint", "RR_calf_joint",  //
    "RL_hip_joint", "RL_thigh_joint", "RL_calf_joint"};
inline constexpr std::array<const char*, kNumLegs> kFootNames = {"FR_foot", "FL_foot", "RR_foot",
                                                                 "RL_foot"};

// Joint ranges (rad): hip +-46 deg, thigh -60..240 deg, calf -154.5..-52.5 deg.
inline constexpr std::array<double, kJointsPerLeg> kLegJointMin = {-0.802851, -1.0472, -2.69653};
inline constexpr std::array<double, kJointsPerLeg> kLegJointMax = {0.802851, 4.18879, -0.916298};
inline constexpr double kTorqueLimit = 33.5;          // N m, every joint
inline constexpr double kJointVelocityLimit = 21.0;  // rad/s, every joint
// rad/s up to which a motor gives its full torque (robot_state.h, DrivingTorqueLimit). Unitree's
// own actuator model for its Go2 motors is flat to 45 % of the no-load speed (13.5 of 30 rad/s),
// then falls linearly; the A1's motors are taken to share that shape.
inline constexpr double kTorqueSpeedKnee = 0.45 * kJointVelocityLimit;
// s a joint may stay past kJointVelocityLimit before skilld's supervisor stops it (by default).
// The motors cannot drive a joint past their no-load speed; a foot strike can, for a tick.
inline constexpr double kJointOverspeedTolerance = 0.04;

inline constexpr double JointMin(int joint) { return kLegJointMin[joint % kJointsPerLeg]; }
inline constexpr double JointMax(int joint) { return kLegJointMax[joint % kJointsPerLeg]; }
// True when q lies in the joint's range widened by `margin` rad at both ends; false for NaN.
inline constexpr bool WithinRange(int joint, double q, double margin) {
  return q >= JointMin(joint) - margin && q <= JointMax(joint) + margin;
}

// legged_gym's A1 default pose (rad): the zero of every action and of the joint observation.
inline constexpr JointArray<double> kDefaultJointPos = {
    -0.1, 0.8, -1.5,  //
    0.1,  0.8, -1.5,  //
    -0.1, 1.0, -1.5,  //
    0.1,  1.0, -1.5};

// Control convention shared by training, simulation and the robot: the policy runs at 50 Hz and
// outputs a; the joint target is q* = q_default + kActionScale * a; the motor PD law
// tau = Kp (q* - q) - Kd qdot runs at every physics step (sim) or in the motor drivers (robot).
inline constexpr double kKp = 20.0;           // N m / rad
inline constexpr double kKd = 0.5;            // N m s / rad
inline constexpr double kActionScale = 0.25;  // rad per unit action
inline constexpr double kActionClip = 100.0;  // |a| beyond this is clipped, as in legged_gym
inline constexpr double kPhysicsDt = 0.005;   // s
inline constexpr int kDecimation = 4;         // physics steps per control step
inline constexpr double kControlDt = kPhysicsDt * kDecimation;  // 0.02 s, 50 Hz

inline constexpr double kFootRadius = 0.02;  // m
inline constexpr double kTotalMass = 12.776;  // kg, from the URDF link masses

}  // namespace flsd::a1
