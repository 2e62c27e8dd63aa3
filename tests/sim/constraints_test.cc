// The constraints a simulated step is measured against, on posed robots with known answers: a
// robot at rest keeps them all; sliding feet, a low base while moving, an overspeeding joint and
// one out of range each violate theirs by the amount they exceed it.

#include "sim/constraints.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "sim/env.h"

namespace flsd {
namespace {

const mjModel& SceneModel() {
  static const MjModelPtr model = LoadMjModel("robot/a1/scene.xml");
  return *model;
}

// The nominal A1 standing in the default pose at rest, with constraints measured.
Env StandingEnv() {
  EnvConfig config;
  config.randomization.DisableAll();
  config.reset.standing_fraction = 1.0;
  Env env(SceneModel(), config, 3);
  for (int t = 0; t < 25; ++t) env.StepCommand(JointCommand::Track(a1::kDefaultJointPos));  // settle
  return env;
}

float Violation(const Env& env, Constraint c) {
  ConstraintLimits limits;
  limits.enabled = true;
  return MeasureViolations(env, limits)[static_cast<int>(c)];
}

TEST(Constraints, AStandingRobotKeepsEveryConstraint) {
  const Env env = StandingEnv();
  ConstraintLimits limits;
  for (float v : MeasureViolations(env, limits)) EXPECT_EQ(v, 0.0f);
}

TEST(Constraints, FeetCarriedAlongByTheBaseSlideAtItsSpeed) {
  Env env = StandingEnv();
  mjData& d = env.data();
  std::fill(d.qvel, d.qvel + env.model().nv, 0.0);
  d.qvel[env.index().root_qvel] = 0.5;  // the whole robot moves at 0.5 m/s along x
  env.SyncState();
  EXPECT_NEAR(Violation(env, Constraint::kFootSlip), 0.5 - 0.1, 1e-6);
  // Moving, but standing tall: no low-base violation.
  EXPECT_EQ(Violation(env, Constraint::kLowBaseMoving), 0.0f);
}

TEST(Constraints, ALowBaseCountsOnlyWhileMoving) {
  Env env = StandingEnv();
  mjData& d = env.data();
  d.qpos[env.index().root_qpos + 2] = 0.20;
  env.SyncState();
  EXPECT_EQ(Violation(env, Constraint::kLowBaseMoving), 0.0f);  // a still, low posture is fine
  EXPECT_NEAR(BaseHeightShortfall(env.state(), ConstraintLimits{}), 0.24 - 0.20, 1e-6);  // what a trainer may hold it to
  d.qvel[env.index().root_qvel + 5] = 0.8;  // turning at 0.8 rad/s
  env.SyncState();
  EXPECT_NEAR(Violation(env, Constraint::kLowBaseMoving), 0.24 - 0.20, 1e-6);
}

TEST(Constraints, JointsPastTheirSpeedAndRangeViolateByTheExcess) {
  Env env = StandingEnv();
  mjData& d = env.data();
  d.qvel[env.index().qvel[4]] = -23.0;                         // FL thigh, 2 rad/s too fast
  d.qpos[env.index().qpos[8]] = a1::JointMax(8) + 0.05;        // RR calf, 0.05 rad past its range
  env.SyncState();
  EXPECT_NEAR(Violation(env, Constraint::kJointSpeed), 2.0, 1e-5);
  EXPECT_NEAR(Violation(env, Constraint::kJointRange), 0.05, 1e-6);
}

TEST(Constraints, StandingStartsAreTheDefaultPoseAtRestWhateverTheRandomisation) {
  EnvConfig config;  // legged_gym's scattered starts and every randomisation on
  config.reset.standing_fraction = 1.0;
  Env env(SceneModel(), config, 7);
  for (int reset = 0; reset < 3; ++reset) {
    env.Reset();
    for (int j = 0; j < a1::kNumJoints; ++j) {
      EXPECT_DOUBLE_EQ(env.state().joint_position[j], a1::kDefaultJointPos[j]) << j;
      EXPECT_EQ(env.state().joint_velocity[j], 0.0);
    }
    EXPECT_EQ(env.state().base_linear_velocity.norm(), 0.0);
    EXPECT_EQ(env.state().base_angular_velocity.norm(), 0.0);
  }
}

}  // namespace
}  // namespace flsd
