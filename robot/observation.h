#pragma once
// The observation builders shared by training and serving (the paper's Eq. 1 and Eq. 14).
//
// Motion observation o^m (33 floats), scaled as legged_gym scales its observations so that every
// entry is of order one:
//   [0, 3)   base linear velocity, body frame      x 2.0   (m/s)
//   [3, 6)   base angular velocity, body frame     x 0.25  (rad/s)
//   [6, 9)   gravity direction, body frame         x 1.0
//   [9, 21)  joint angle - default pose            x 1.0   (rad)
//   [21, 33) joint velocity                        x 0.05  (rad/s)
// Policy observation o^p = [o^m (33), previous action (12), one-hot skill (N_k)].
// Task observation o^c = [o^m (33), velocity command (vx, vy, wz)]: what the skill selector and
// the from-scratch velocity policy see; the command is scaled as o^m scales the base velocities
// (legged_gym's commands_scale).

#include <array>

#include "robot/robot_state.h"

namespace flsd {

struct ObservationSegment {
  const char* name;
  int offset;
  int size;
  double scale;  // observation = scale * physical value
};

inline constexpr int kMotionObsSize = 33;
inline constexpr std::array<ObservationSegment, 5> kMotionObsLayout = {{
    {"base_lin_vel", 0, 3, 2.0},
    {"base_ang_vel", 3, 3, 0.25},
    {"projected_gravity", 6, 3, 1.0},
    {"joint_pos", 9, a1::kNumJoints, 1.0},
    {"joint_vel", 21, a1::kNumJoints, 0.05},
}};

// Writes o^m for `state` into out[0, kMotionObsSize).
void BuildMotionObservation(const RobotState& state, float* out);

inline constexpr int kActionSize = a1::kNumJoints;
inline constexpr int PolicyObservationSize(int num_skills) {
  return kMotionObsSize + kActionSize + num_skills;
}

// Writes o^p into out[0, PolicyObservationSize(num_skills)). Throws InputError if `skill` is not
// in [0, num_skills).
void BuildPolicyObservation(const float* motion_obs, const float* previous_action, int skill,
                            int num_skills, float* out);

inline constexpr int kCommandSize = 3;
inline constexpr int kTaskObsSize = kMotionObsSize + kCommandSize;

// Writes o^c into out[0, kTaskObsSize). command: (vx, vy) m/s and wz rad/s, body frame.
void BuildTaskObservation(const float* motion_obs, const double* command, float* out);

// Joint targets q* = q_default + kActionScale * clip(a) for a policy action.
a1::JointArray<double> JointTargetsFromAction(const float* action);

}  // namespace flsd
