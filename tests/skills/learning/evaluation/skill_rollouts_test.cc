// The env a skill is evaluated in: nominal, randomised as in training, or randomised from a
// standing start (the physics and pushes randomised, the start as skilld's: the default pose at rest).

#include "skills/learning/evaluation/skill_rollouts.h"

#include <gtest/gtest.h>

#include "robot/a1.h"
#include "sim/mujoco_model.h"

namespace flsd {
namespace {

const mjModel& SceneModel() {
  static const MjModelPtr model = LoadMjModel("robot/a1/scene.xml");
  return *model;
}

// The largest departure of a reset from the default pose at rest, over `resets` resets.
struct StartSpread {
  double joint = 0.0;     // rad
  double velocity = 0.0;  // m/s of the base
  double friction_lo = 1e9, friction_hi = -1e9;
};

StartSpread SpreadOfStarts(const EnvConfig& config, int resets) {
  Env env(SceneModel(), config, 7);
  StartSpread spread;
  for (int r = 0; r < resets; ++r) {
    env.Reset();
    for (int j = 0; j < a1::kNumJoints; ++j) {
      spread.joint = std::max(spread.joint, std::abs(env.state().joint_position[j] - a1::kDefaultJointPos[j]));
    }
    spread.velocity = std::max(spread.velocity, env.state().base_linear_velocity.norm());
    spread.friction_lo = std::min(spread.friction_lo, env.randomization().friction);
    spread.friction_hi = std::max(spread.friction_hi, env.randomization().friction);
  }
  return spread;
}

EnvConfig TrainingEnv() {
  EnvConfig c;  // legged_gym's tossed reset and friction 0.5-1.25
  c.randomization.friction.enabled = true;
  c.randomization.friction.range = {0.5, 1.25};
  c.reset.joint_pos_scale = {0.5, 1.5};
  c.reset.base_velocity = 0.5;
  return c;
}

TEST(EvaluationEnvConfig, NominalStartsAtRestWithTheNominalPhysics) {
  const StartSpread s = SpreadOfStarts(EvaluationEnvConfig(TrainingEnv(), EvaluationOptions{}), 20);
  EXPECT_LT(s.joint, 1e-9);
  EXPECT_LT(s.velocity, 1e-9);
  EXPECT_EQ(s.friction_lo, 1.0);
  EXPECT_EQ(s.friction_hi, 1.0);
}

TEST(EvaluationEnvConfig, RandomizedTossesTheStartAsTrainingDoes) {
  EvaluationOptions options;
  options.randomize = true;
  const StartSpread s = SpreadOfStarts(EvaluationEnvConfig(TrainingEnv(), options), 20);
  EXPECT_GT(s.joint, 0.2);      // joints at 0.5-1.5 times the default pose
  EXPECT_GT(s.velocity, 0.2);   // each base velocity up to 0.5 m/s
  EXPECT_LT(s.friction_lo, 0.8);
  EXPECT_GT(s.friction_hi, 1.0);
}

TEST(EvaluationEnvConfig, AStandingStartKeepsThePhysicsRandomizedButStartsAtRest) {
  EvaluationOptions options;
  options.randomize = true;
  options.standing_start = true;
  const EnvConfig env = EvaluationEnvConfig(TrainingEnv(), options);
  const StartSpread s = SpreadOfStarts(env, 20);
  EXPECT_LT(s.joint, 1e-9);
  EXPECT_LT(s.velocity, 1e-9);
  EXPECT_LT(s.friction_lo, 0.8);
  EXPECT_GT(s.friction_hi, 1.0);
  EXPECT_EQ(env.episode_steps, TrainingEnv().episode_steps + 1);  // no reset inside the record
}

TEST(EvaluationEnvConfig, AStandingStartAloneChangesNothing) {
  EvaluationOptions options;
  options.standing_start = true;  // without randomize the start is at rest anyway
  const StartSpread s = SpreadOfStarts(EvaluationEnvConfig(TrainingEnv(), options), 5);
  EXPECT_LT(s.joint, 1e-9);
  EXPECT_EQ(s.friction_lo, 1.0);
}

}  // namespace
}  // namespace flsd
