#include "sim/env.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <set>
#include <string>

#include "robot/observation.h"
#include "tests/common/sim_printers.h"
#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testutil::InputErrorMessage;
using testutil::TempFile;

using Action = std::array<float, kActionSize>;
using Strengths = a1::JointArray<double>;

constexpr double kGravity = 9.81;  // MuJoCo's default |g|, which the scene keeps

const mjModel& SceneModel() {
  static const MjModelPtr model = LoadMjModel("robot/a1/scene.xml");
  return *model;
}

// No randomisation and an exact default pose at rest: every reset gives the same state.
EnvConfig DeterministicConfig() {
  EnvConfig c;
  c.randomization.DisableAll();
  c.reset.base_velocity = 0.0;
  c.reset.joint_pos_scale = {1.0, 1.0};
  return c;
}

Action Filled(float value) {
  Action a;
  a.fill(value);
  return a;
}

// A nonzero action with both signs and different sizes per joint.
Action Varied() {
  Action a;
  for (int j = 0; j < kActionSize; ++j) a[j] = static_cast<float>(0.8 * std::sin(1.7 * (j + 1)));
  return a;
}

MjDataPtr CopyData(const Env& env) {
  MjDataPtr copy(mj_makeData(&env.model()));
  mj_copyData(copy.get(), &env.model(), &env.data());
  return copy;
}

// One control step done by hand: the PD law toward q0 + 0.25 a at each of the 4 physics steps,
// with the gains written out (Kp 20, Kd 0.5) rather than taken from a1.h, and the motors'
// torque-speed line on, as EnvConfig has it by default.
void ReplayControlStep(const Env& env, mjData& d, const Action& action, const Strengths& strength) {
  const A1ModelIndex& index = env.index();
  for (int substep = 0; substep < a1::kDecimation; ++substep) {
    for (int j = 0; j < a1::kNumJoints; ++j) {
      const double target = a1::kDefaultJointPos[j] + 0.25 * static_cast<double>(action[j]);
      d.ctrl[index.actuator[j]] = MotorTorque(20.0, 0.5, target, 0.0, d.qpos[index.qpos[j]],
                                              d.qvel[index.qvel[j]], 0.0, strength[j], true);
    }
    mj_step(&env.model(), &d);
  }
}

void ExpectSameState(const mjModel& m, const mjData& a, const mjData& b, double tol) {
  for (int i = 0; i < m.nq; ++i) EXPECT_NEAR(a.qpos[i], b.qpos[i], tol) << "qpos " << i;
  for (int i = 0; i < m.nv; ++i) EXPECT_NEAR(a.qvel[i], b.qvel[i], tol) << "qvel " << i;
}

Eigen::Quaterniond Roll(double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()));
}

// Poses the base at (0, 0, z) with orientation q; the joints stay as they are.
void PoseBase(Env& env, double z, const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  mjtNum* root = env.data().qpos + env.index().root_qpos;
  root[0] = root[1] = 0.0;
  root[2] = z;
  root[3] = q.w();
  root[4] = q.x();
  root[5] = q.y();
  root[6] = q.z();
  env.SyncState();
}

// Deterministic, except for the one randomisation `field`, drawn from `range`.
EnvConfig WithOnly(RandomRange RandomizationConfig::*field, Interval range) {
  EnvConfig c = DeterministicConfig();
  (c.randomization.*field).enabled = true;
  (c.randomization.*field).range = range;
  return c;
}

// The action that holds joint pose `q`.
Action HoldPose(const a1::JointArray<double>& q) {
  Action a;
  for (int j = 0; j < kActionSize; ++j) {
    a[j] = static_cast<float>((q[j] - a1::kDefaultJointPos[j]) / 0.25);
  }
  return a;
}

void StandStill(Env& env, int steps) {
  const Action zero = Filled(0.0f);
  for (int t = 0; t < steps; ++t) {
    ASSERT_EQ(env.Step(zero.data()), Termination::kNone) << "step " << t;
  }
}

// Collects MuJoCo's warnings instead of letting it print them and write MUJOCO_LOG.TXT.
class CaptureMuJoCoWarnings {
 public:
  CaptureMuJoCoWarnings() : previous_(mju_user_warning) {
    messages_().clear();
    mju_user_warning = [](const char* message) { messages_() += message; };
  }
  ~CaptureMuJoCoWarnings() { mju_user_warning = previous_; }
  const std::string& text() const { return messages_(); }

 private:
  static std::string& messages_() {
    static std::string messages;
    return messages;
  }
  void (*previous_)(const char*);
};

double TotalFootForce(const RobotState& s) {
  double total = 0.0;
  for (double f : s.foot_force) total += f;
  return total;
}

// ---- standing and the control law ----

TEST(Env, ZeroActionStandsOnFourFeet) {
  Env env(SceneModel(), DeterministicConfig(), 1);
  ASSERT_NO_FATAL_FAILURE(StandStill(env, 100));
  const RobotState& s = env.state();
  EXPECT_NEAR(s.time, 100 * a1::kControlDt, 1e-9);
  EXPECT_GE(s.base_position.z(), 0.22);
  EXPECT_LE(s.base_position.z(), 0.32);
  for (int leg = 0; leg < a1::kNumLegs; ++leg) {
    EXPECT_TRUE(s.foot_contact[leg]) << a1::kLegNames[leg];
  }
  // The calves stop short of the feet, so a stance touches the floor with the four feet only.
  EXPECT_EQ(env.data().ncon, 4);
  EXPECT_FALSE(env.calf_contact());
  // At rest the feet carry the weight.
  EXPECT_NEAR(TotalFootForce(s), a1::kTotalMass * kGravity, 0.1 * a1::kTotalMass * kGravity);
}

TEST(Env, StanceFootSpeedIsZeroStandingAndTheBaseSpeedWhenTheWholeRobotSlides) {
  Env env(SceneModel(), DeterministicConfig(), 1);
  ASSERT_NO_FATAL_FAILURE(StandStill(env, 100));
  EXPECT_LT(env.StanceFootSpeed(), 0.01);
  // Every body moving at (0.6, 0.8, 0) m/s with no rotation: each foot slides at 1 m/s.
  mjData& d = env.data();
  for (int i = 0; i < env.model().nv; ++i) d.qvel[i] = 0.0;
  d.qvel[env.index().root_qvel + 0] = 0.6;
  d.qvel[env.index().root_qvel + 1] = 0.8;
  env.SyncState();
  EXPECT_NEAR(env.StanceFootSpeed(), 1.0, 1e-9);
}

// How far the feet of the robot, standing in the default pose, creep in 2 s under a horizontal
// push on the trunk of `share` of its weight (the friction cone, coefficient 1, holds feet up to a
// share of 1; the stance itself gives way at about 0.2).
double FootCreepUnderAPush(const std::string& scene, double share) {
  const MjModelPtr model = LoadMjModel(scene);
  Env env(*model, DeterministicConfig(), 1);
  StandStill(env, 100);
  if (::testing::Test::HasFatalFailure()) return NAN;  // fell: no creep to measure
  auto foot = [&](int leg) {
    const mjtNum* p = env.data().geom_xpos + 3 * env.index().foot_geom[leg];
    return Eigen::Vector2d(p[0], p[1]);
  };
  std::array<Eigen::Vector2d, a1::kNumLegs> start;
  for (int leg = 0; leg < a1::kNumLegs; ++leg) start[leg] = foot(leg);
  const int trunk = mj_name2id(&env.model(), mjOBJ_BODY, "trunk");
  env.data().xfrc_applied[6 * trunk] = share * a1::kTotalMass * kGravity;
  StandStill(env, 100);
  if (::testing::Test::HasFatalFailure()) return NAN;
  double creep = 0.0;
  for (int leg = 0; leg < a1::kNumLegs; ++leg) creep = std::max(creep, (foot(leg) - start[leg]).norm());
  return creep;
}

// MuJoCo's contacts are soft: under the pyramidal cone with impratio 1, loaded feet creep well
// inside the friction cone. scene_hard_friction.xml is the same robot and floor with the elliptic
// cone and impratio 10.
TEST(Env, OnTheHardFrictionSceneLoadedFeetCreepLess) {
  const MjModelPtr hard = LoadMjModel("robot/a1/scene_hard_friction.xml");
  EXPECT_EQ(hard->opt.cone, mjCONE_ELLIPTIC);
  EXPECT_EQ(hard->opt.impratio, 10.0);
  EXPECT_EQ(hard->nbody, SceneModel().nbody);  // the same robot and floor
  EXPECT_EQ(hard->ngeom, SceneModel().ngeom);
  // A tenth of the weight, well inside the friction cone: 43 mm of creep against 7 mm.
  const double soft = FootCreepUnderAPush("robot/a1/scene.xml", 0.1);
  const double stiff = FootCreepUnderAPush("robot/a1/scene_hard_friction.xml", 0.1);
  EXPECT_GT(soft, 0.02);
  EXPECT_LT(stiff, 0.25 * soft);
}

TEST(Env, FootContactIsReportedPerLeg) {
  Env env(SceneModel(), DeterministicConfig(), 1);
  ASSERT_NO_FATAL_FAILURE(StandStill(env, 100));
  for (int lifted = 0; lifted < a1::kNumLegs; ++lifted) {
    // Folding the calf to its limit swings the foot up in front of the knee.
    mjtNum& calf = env.data().qpos[env.index().qpos[a1::kJointsPerLeg * lifted + 2]];
    const mjtNum standing = calf;
    calf = a1::JointMin(2);
    env.SyncState();
    for (int leg = 0; leg < a1::kNumLegs; ++leg) {
      EXPECT_EQ(env.state().foot_contact[leg], leg != lifted)
          << a1::kLegNames[leg] << " with " << a1::kLegNames[lifted] << " lifted";
    }
    EXPECT_EQ(env.state().foot_force[lifted], 0.0);
    calf = standing;
  }
}

TEST(Env, StateReportsBodyFrameBaseVelocities) {
  Env env(SceneModel(), DeterministicConfig(), 1);
  mjtNum* v = env.data().qvel + env.index().root_qvel;
  const mjtNum world_linear[3] = {1.0, 0.0, 0.5}, body_angular[3] = {0.1, 0.2, 0.3};
  std::copy(world_linear, world_linear + 3, v);
  std::copy(body_angular, body_angular + 3, v + 3);
  // Yawed 90 deg: the body x axis is the world y axis and the body y axis the world -x axis, so
  // moving along world x is moving along body -y.
  PoseBase(env, 1.0, Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())));
  const RobotState& s = env.state();
  EXPECT_NEAR(s.base_linear_velocity.x(), 0.0, 1e-12);
  EXPECT_NEAR(s.base_linear_velocity.y(), -1.0, 1e-12);
  EXPECT_NEAR(s.base_linear_velocity.z(), 0.5, 1e-12);
  // MuJoCo keeps a free joint's angular velocity in the body frame already.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.base_angular_velocity[k], body_angular[k], 1e-12);
  // And MuJoCo agrees: the velocity of the trunk's body frame (mjOBJ_XBODY; mjOBJ_BODY would be
  // its inertial frame) in that frame, [angular, linear].
  mjtNum local[6];
  mj_objectVelocity(&env.model(), &env.data(), mjOBJ_XBODY, env.index().trunk_body, local, 1);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(s.base_angular_velocity[k], local[k], 1e-12);
    EXPECT_NEAR(s.base_linear_velocity[k], local[3 + k], 1e-12);
  }
}

TEST(Env, StepAppliesThePdLawAtEveryPhysicsStep) {
  Env env(SceneModel(), DeterministicConfig(), 2);
  const Action action = Varied();
  MjDataPtr replay = CopyData(env);
  ASSERT_EQ(env.Step(action.data()), Termination::kNone);
  Strengths full;
  full.fill(1.0);
  ReplayControlStep(env, *replay, action, full);
  ExpectSameState(env.model(), env.data(), *replay, 1e-12);
  // The reported torque is the one applied in the last physics step.
  for (int j = 0; j < a1::kNumJoints; ++j) {
    EXPECT_EQ(env.state().joint_torque[j], replay->ctrl[env.index().actuator[j]])
        << a1::kJointNames[j];
  }
}

TEST(Env, LargeActionSaturatesAtTheTorqueLimit) {
  EnvConfig config = DeterministicConfig();
  config.torque_speed_limit = false;  // the stall torque alone; the speed line is tested below
  Env env(SceneModel(), config, 3);
  Action action;
  for (int j = 0; j < kActionSize; ++j) action[j] = j % 2 == 0 ? 50.0f : -50.0f;  // 12.5 rad away
  env.Step(action.data());
  for (int j = 0; j < a1::kNumJoints; ++j) {
    EXPECT_EQ(env.state().joint_torque[j], j % 2 == 0 ? a1::kTorqueLimit : -a1::kTorqueLimit)
        << a1::kJointNames[j];
  }
}

// The fastest a thigh swings, from the default pose in the air to its upper stop, driven at full
// torque toward a target far beyond it.
double FastestThighSwing(bool torque_speed_limit) {
  EnvConfig config = DeterministicConfig();
  config.torque_speed_limit = torque_speed_limit;
  Env env(SceneModel(), config, 5);
  PoseBase(env, 1.0);
  JointCommand command = JointCommand::Track(a1::kDefaultJointPos);
  for (int leg = 0; leg < a1::kNumLegs; ++leg) command.position[3 * leg + 1] = 12.0;
  double fastest = 0.0;
  for (int step = 0; step < 60; ++step) {
    env.StepCommand(command, 1);
    for (int leg = 0; leg < a1::kNumLegs; ++leg) {
      const int thigh = 3 * leg + 1;
      if (env.state().joint_position[thigh] > a1::JointMax(thigh) - 0.05) return fastest;  // at the stop
      fastest = std::max(fastest, std::abs(env.state().joint_velocity[thigh]));
    }
  }
  return fastest;
}

TEST(Env, TheMotorsTorqueSpeedLineKeepsAJointUnderTheA1sSpeedLimit) {
  // The line itself: full torque at rest, half at half speed, none at 21 rad/s, either way.
  EXPECT_EQ(DrivingTorqueLimit(0.0), 33.5);
  EXPECT_DOUBLE_EQ(DrivingTorqueLimit(-10.5), 16.75);
  EXPECT_EQ(DrivingTorqueLimit(21.0), 0.0);
  EXPECT_EQ(DrivingTorqueLimit(30.0), 0.0);
  // It limits torque along the motion only; braking keeps the stall torque.
  EXPECT_DOUBLE_EQ(MotorTorque(20.0, 0.5, 10.0, 0.0, 0.0, 10.5, 0.0, 1.0, true), 16.75);
  EXPECT_EQ(MotorTorque(20.0, 0.5, -10.0, 0.0, 0.0, 10.5, 0.0, 1.0, true), -33.5);
  EXPECT_EQ(MotorTorque(20.0, 0.5, 10.0, 0.0, 0.0, 10.5, 0.0, 1.0, false), 33.5);
  // With the knee at 45 % of 21 rad/s: full torque to 9.45 rad/s, then a line to none at 21.
  EXPECT_EQ(DrivingTorqueLimit(9.45, a1::kTorqueSpeedKnee), 33.5);
  EXPECT_NEAR(DrivingTorqueLimit(-15.225, a1::kTorqueSpeedKnee), 16.75, 1e-9);
  EXPECT_EQ(DrivingTorqueLimit(21.0, a1::kTorqueSpeedKnee), 0.0);
  EXPECT_NEAR(MotorTorque(20.0, 0.5, 10.0, 0.0, 0.0, 15.225, 0.0, 1.0, true, a1::kTorqueSpeedKnee), 16.75, 1e-9);
  // In the simulator: a thigh swung at full torque reaches 84 rad/s without the line; with it, it
  // creeps up to the no-load speed, and gravity and the trunk's counter-rotation carry it a few
  // percent past (21.6 rad/s measured).
  EXPECT_GT(FastestThighSwing(false), 60.0);
  const double limited = FastestThighSwing(true);
  EXPECT_GT(limited, 0.95 * a1::kJointVelocityLimit);
  EXPECT_LT(limited, 1.05 * a1::kJointVelocityLimit);
}

TEST(Env, TheTargetFilterMovesTheFirstTargetPartWayFromThePoseAtReset) {
  // From the exact default pose, a 4 Hz filter's first target is q0 + g 0.25 a with g = 0.395:
  // the same step as the unfiltered env given g a.
  EnvConfig config = DeterministicConfig();
  config.action_filter_hz = 4.0;
  Env env(SceneModel(), config, 2);
  const Action action = Varied();
  MjDataPtr replay = CopyData(env);
  ASSERT_EQ(env.Step(action.data()), Termination::kNone);
  const double g = 1.0 - std::exp(-2.0 * M_PI * 4.0 * a1::kControlDt);
  Action part_way;
  for (int j = 0; j < kActionSize; ++j) part_way[j] = static_cast<float>(g * action[j]);
  Strengths full;
  full.fill(1.0);
  ReplayControlStep(env, *replay, part_way, full);
  ExpectSameState(env.model(), env.data(), *replay, 1e-6);
}

TEST(Env, MotorStrengthScalesThePdTorque) {
  Env env(SceneModel(), WithOnly(&RandomizationConfig::motor_strength, {0.5, 0.5}), 4);
  for (double s : env.randomization().motor_strength) EXPECT_EQ(s, 0.5);

  const Action action = Varied();
  MjDataPtr replay = CopyData(env);
  env.Step(action.data());
  Strengths half;
  half.fill(0.5);
  ReplayControlStep(env, *replay, action, half);
  ExpectSameState(env.model(), env.data(), *replay, 1e-12);
}

// An env with a delay of d control steps fed [a, 0, ..., 0] moves exactly like an undelayed one
// fed [0, ..., 0, a]. d = 4 is the longest delay the action history holds.
class EnvActionDelay : public ::testing::TestWithParam<int> {};

TEST_P(EnvActionDelay, DelayedActionEqualsTheSameActionSentLater) {
  const int delay = GetParam();
  Env delayed(SceneModel(),
              WithOnly(&RandomizationConfig::action_delay, {double(delay), double(delay)}), 5);
  Env direct(SceneModel(), DeterministicConfig(), 5);
  ASSERT_EQ(delayed.randomization().action_delay, delay);
  ASSERT_EQ(direct.randomization().action_delay, 0);
  // The reset pose does not depend on the random stream here, so both start alike.
  ASSERT_EQ(std::memcmp(delayed.data().qpos, direct.data().qpos, sizeof(mjtNum) * SceneModel().nq),
            0);

  const Action a = Varied(), zero = Filled(0.0f);
  for (int t = 0; t <= delay; ++t) {
    delayed.Step((t == 0 ? a : zero).data());
    direct.Step((t == delay ? a : zero).data());
    ExpectSameState(SceneModel(), delayed.data(), direct.data(), 1e-12);
  }
}

INSTANTIATE_TEST_SUITE_P(Steps, EnvActionDelay, ::testing::Values(1, 4));

// ---- reset ----

TEST(EnvReset, DrawsThePoseWithinTheConfigAndPutsTheLowestFootAtClearance) {
  EnvConfig config;  // default reset draws: joints x U(0.5, 1.5), base velocities U(-0.5, 0.5)
  config.reset.foot_clearance = 0.03;
  Env env(SceneModel(), config, 30);
  std::set<double> first_joint;
  for (int reset = 0; reset < 10; ++reset) {
    env.Reset();
    const mjData& d = env.data();
    double lowest = INFINITY;
    for (int g : env.index().foot_geom) {
      lowest = std::min(lowest, d.geom_xpos[3 * g + 2] - a1::kFootRadius);
    }
    EXPECT_NEAR(lowest, 0.03, 1e-12);
    for (int j = 0; j < a1::kNumJoints; ++j) {
      const double q = env.state().joint_position[j];
      const double scale = q / a1::kDefaultJointPos[j];
      const bool clipped = q == a1::JointMin(j) || q == a1::JointMax(j);
      EXPECT_TRUE(clipped || (scale >= 0.5 && scale <= 1.5)) << a1::kJointNames[j] << " = " << q;
      EXPECT_GE(q, a1::JointMin(j));
      EXPECT_LE(q, a1::JointMax(j));
      EXPECT_EQ(env.state().joint_velocity[j], 0.0);
    }
    for (int k = 0; k < 6; ++k) EXPECT_LE(std::abs(d.qvel[env.index().root_qvel + k]), 0.5);
    EXPECT_EQ(env.state().base_orientation.w(), 1.0);
    EXPECT_EQ(env.state().time, 0.0);
    first_joint.insert(env.state().joint_position[0]);
  }
  EXPECT_EQ(first_joint.size(), 10u);
}

TEST(EnvReset, ClearsTheActionHistory) {
  // With the longest delay, every action still queued at a reset would act in the new episode;
  // fill the whole queue, reset, and the next steps must be plain zero-action PD steps.
  constexpr int kDelay = RandomizationConfig::kMaxActionDelay;
  Env env(SceneModel(),
          WithOnly(&RandomizationConfig::action_delay, {double(kDelay), double(kDelay)}), 31);
  for (int t = 0; t <= kDelay; ++t) env.Step(Varied().data());
  env.Reset();
  const Action zero = Filled(0.0f);
  Strengths full;
  full.fill(1.0);
  for (int t = 0; t < kDelay; ++t) {
    MjDataPtr replay = CopyData(env);
    env.Step(zero.data());
    ReplayControlStep(env, *replay, zero, full);
    ExpectSameState(env.model(), env.data(), *replay, 1e-12);
  }
}

// ---- termination ----

TEST(EnvTermination, UpsideDownInTheAirIsTilt) {
  // Trunk 0.2 m up, legs pointing at the sky: nothing touches the floor in the first step, and
  // the body z axis points down, far past max_tilt.
  Env env(SceneModel(), DeterministicConfig(), 6);
  PoseBase(env, 0.2, Roll(M_PI));
  const Termination t = env.Step(Filled(0.0f).data());
  EXPECT_EQ(t, Termination::kTilt);
  EXPECT_TRUE(IsFailure(t));
}

TEST(EnvTermination, UpsideDownOnTheFloorIsBodyContact) {
  // The trunk (half height 0.057) sinks 2.7 cm into the floor; contact is checked before tilt.
  Env env(SceneModel(), DeterministicConfig(), 7);
  PoseBase(env, 0.03, Roll(M_PI));
  const Termination t = env.Step(Filled(0.0f).data());
  EXPECT_EQ(t, Termination::kBodyContact);
  EXPECT_TRUE(IsFailure(t));
}

TEST(EnvTermination, TiltBeyondMaxTiltEndsTheEpisode) {
  // 1 m up, so no contact: only the attitude decides. max_tilt is 1.2 rad.
  for (const auto& [roll, expected] :
       {std::pair{1.3, Termination::kTilt}, std::pair{-1.3, Termination::kTilt},
        std::pair{1.1, Termination::kNone}}) {
    Env env(SceneModel(), DeterministicConfig(), 8);
    PoseBase(env, 1.0, Roll(roll));
    const Termination t = env.Step(Filled(0.0f).data());
    EXPECT_EQ(t, expected) << "roll " << roll << ": ";
  }
}

TEST(EnvTermination, BaseBelowMinHeightIsLowBase) {
  EnvConfig config = DeterministicConfig();
  config.termination.limits.min_base_height = 0.5;  // above the standing height
  Env env(SceneModel(), config, 9);
  const Termination t = env.Step(Filled(0.0f).data());
  EXPECT_EQ(t, Termination::kLowBase);
  EXPECT_TRUE(IsFailure(t));
}

TEST(EnvTermination, JointFasterThanMaxJointSpeedEndsTheEpisode) {
  // A large action swings the joints; the fastest one after the step sets the threshold: with no
  // time allowed past it, a limit just below it ends the episode, one just above does not, and 0
  // (the default) never does.
  const Action swing = Filled(4.0f);
  EnvConfig config = DeterministicConfig();
  config.termination.limits.max_joint_speed_time = 0.0;
  Env free_env(SceneModel(), config, 11);
  ASSERT_EQ(free_env.Step(swing.data()), Termination::kNone);
  double fastest = 0.0;
  for (double qd : free_env.state().joint_velocity) fastest = std::max(fastest, std::abs(qd));
  ASSERT_GT(fastest, 1.0);
  for (const auto& [limit, expected] :
       {std::pair{0.99 * fastest, Termination::kJointSpeed}, std::pair{1.01 * fastest, Termination::kNone}}) {
    config.termination.limits.max_joint_speed = limit;
    Env env(SceneModel(), config, 11);
    const Termination t = env.Step(swing.data());
    EXPECT_EQ(t, expected) << "limit " << limit << " rad/s, fastest joint " << fastest;
    if (t == Termination::kJointSpeed) {
      EXPECT_TRUE(IsFailure(t));
    }
  }
  EXPECT_STREQ(ToString(Termination::kJointSpeed), "joint_speed");
}

TEST(EnvTermination, AJointPastMaxJointSpeedEndsTheEpisodeOnlyAfterMaxJointSpeedTime) {
  // The supervisor's rule (a1::kJointOverspeedTolerance, 0.04 s): the joints swinging to a far
  // target stay past a tiny limit at every 20 ms step, so the episode goes on at 0.02 and 0.04 s
  // and ends at 0.06 s; a reset starts the count again.
  const Action swing = Filled(4.0f);
  EnvConfig config = DeterministicConfig();
  config.termination.limits.max_joint_speed = 1e-3;
  ASSERT_DOUBLE_EQ(config.termination.limits.max_joint_speed_time, a1::kJointOverspeedTolerance);
  Env env(SceneModel(), config, 11);
  for (int round = 0; round < 2; ++round) {
    EXPECT_EQ(env.Step(swing.data()), Termination::kNone) << "round " << round;
    EXPECT_EQ(env.Step(swing.data()), Termination::kNone) << "round " << round;
    EXPECT_EQ(env.Step(swing.data()), Termination::kJointSpeed) << "round " << round;
    env.Reset();
  }
}

TEST(EnvTermination, AJointFurtherOutOfRangeThanTheMarginEndsTheEpisode) {
  // The FR hip posed 0.3 rad past its range: how far out it still is after one step sets the
  // margin. A margin just under that ends the episode, one just over does not, negative is off.
  EnvConfig config = DeterministicConfig();
  auto step_from_outside = [&](double margin) {
    config.termination.limits.joint_range_margin = margin;
    Env env(SceneModel(), config, 13);
    env.data().qpos[env.index().qpos[0]] = a1::JointMin(0) - 0.3;
    env.SyncState();
    const Termination t = env.Step(Filled(0.0f).data());
    return std::pair{t, a1::JointMin(0) - env.state().joint_position[0]};
  };
  const auto [off, excess] = step_from_outside(-1.0);
  EXPECT_EQ(off, Termination::kNone);
  ASSERT_GT(excess, 0.01) << "the hip came back into range within one step";
  EXPECT_EQ(step_from_outside(0.9 * excess).first, Termination::kJointRange);
  EXPECT_EQ(step_from_outside(1.1 * excess).first, Termination::kNone);
  EXPECT_TRUE(IsFailure(Termination::kJointRange));
  EXPECT_STREQ(ToString(Termination::kJointRange), "joint_range");
}

TEST(EnvTermination, EpisodeStepsEndsWithTimeOutWhichIsNoFailure) {
  EnvConfig config = DeterministicConfig();
  config.episode_steps = 3;
  Env env(SceneModel(), config, 10);
  const Action zero = Filled(0.0f);
  EXPECT_EQ(env.Step(zero.data()), Termination::kNone);
  EXPECT_EQ(env.Step(zero.data()), Termination::kNone);
  const Termination t = env.Step(zero.data());
  EXPECT_EQ(t, Termination::kTimeOut);
  EXPECT_FALSE(IsFailure(t));
  EXPECT_EQ(env.episode_step(), 3);
  env.Reset();
  EXPECT_EQ(env.episode_step(), 0);
}

TEST(EnvTermination, NonFiniteActionIsRejectedAndNotApplied) {
  Env env(SceneModel(), DeterministicConfig(), 11);
  env.Step(Varied().data());  // so that the state is not the reset one
  const int nq = env.model().nq, nv = env.model().nv;
  for (float bad : {NAN, INFINITY, -INFINITY}) {
    MjDataPtr before = CopyData(env);
    Action action = Varied();
    action[7] = bad;
    EXPECT_EQ(env.Step(action.data()), Termination::kInvalidAction);
    EXPECT_EQ(env.episode_step(), 1);
    EXPECT_EQ(env.data().time, before->time);
    EXPECT_EQ(std::memcmp(env.data().qpos, before->qpos, sizeof(mjtNum) * nq), 0);
    EXPECT_EQ(std::memcmp(env.data().qvel, before->qvel, sizeof(mjtNum) * nv), 0);
  }
  // Nor did it enter the action history: the next valid step is the plain PD step.
  MjDataPtr replay = CopyData(env);
  const Action zero = Filled(0.0f);
  env.Step(zero.data());
  Strengths full;
  full.fill(1.0);
  ReplayControlStep(env, *replay, zero, full);
  ExpectSameState(env.model(), env.data(), *replay, 1e-12);
}

// Kneeling: thighs at 1.0 rad and calves folded to -2.69 rad put the knees lowest (calf bottom
// 0.111 m below the trunk centre, thigh bottom 0.100 m, trunk 0.057 m, feet above the knees); at a
// base height of 0.106 m the calves touch the floor and nothing else does.
a1::JointArray<double> KneelingPose() {
  a1::JointArray<double> q = a1::kDefaultJointPos;
  for (int leg = 0; leg < a1::kNumLegs; ++leg) {
    q[a1::kJointsPerLeg * leg + 1] = 1.0;
    q[a1::kJointsPerLeg * leg + 2] = -2.69;
  }
  return q;
}

TEST(EnvTermination, CalfContactIsAKneeStrikeThatEndsOnlyWhenConfigured) {
  for (bool on_calf_contact : {false, true}) {
    EnvConfig config = DeterministicConfig();
    config.termination.on_calf_contact = on_calf_contact;
    Env env(SceneModel(), config, 19);
    const a1::JointArray<double> kneel = KneelingPose();
    for (int j = 0; j < a1::kNumJoints; ++j) env.data().qpos[env.index().qpos[j]] = kneel[j];
    PoseBase(env, 0.106);
    EXPECT_TRUE(env.calf_contact());
    const Termination t = env.Step(HoldPose(kneel).data());
    EXPECT_TRUE(env.calf_contact());
    for (bool foot : env.state().foot_contact) EXPECT_FALSE(foot);
    EXPECT_EQ(t, on_calf_contact ? Termination::kBodyContact : Termination::kNone)
        << "on_calf_contact " << on_calf_contact << ": ";
  }
}

// A joint spinning at 1e6 rad/s makes MuJoCo's accelerations blow up (mjWARN_BADQACC).
TEST(EnvTermination, BlowUpIsPhysics) {
  const CaptureMuJoCoWarnings warnings;
  Env env(SceneModel(), DeterministicConfig(), 21);
  env.data().qvel[env.index().qvel[4]] = 1e6;
  env.SyncState();
  const Termination t = env.Step(Filled(0.0f).data());
  EXPECT_EQ(t, Termination::kPhysics);
  EXPECT_TRUE(IsFailure(t));
  EXPECT_THAT(warnings.text(), HasSubstr("QACC"));
}

// kPhysics is documented to cover a non-finite state. MuJoCo answers a NaN (or > 1e10) qpos or
// qvel at the start of mj_step by warning (mjWARN_BADQPOS / mjWARN_BADQVEL) and resetting mjData
// to the model's qpos0 itself, so the episode must end there rather than go on from qpos0.
// Fails as of this writing: Env::Step looks at mjWARN_BADQACC only (sim/env.cc).
TEST(EnvTermination, NonFiniteStateEndsTheEpisodeAsPhysics) {
  for (const bool in_velocity : {false, true}) {
    const CaptureMuJoCoWarnings warnings;
    Env env(SceneModel(), DeterministicConfig(), 20);
    const Action zero = Filled(0.0f);
    env.Step(zero.data());
    const int j = 4;  // FL thigh
    (in_velocity ? env.data().qvel[env.index().qvel[j]] : env.data().qpos[env.index().qpos[j]]) =
        NAN;
    env.SyncState();
    const Termination t = env.Step(zero.data());
    EXPECT_EQ(t, Termination::kPhysics)
        << "NaN in " << (in_velocity ? "qvel" : "qpos") << " gave " << ToString(t) << "; time is "
        << env.data().time << " s, 0.04 s if nothing restarted; MuJoCo said: " << warnings.text();
  }
}

// ---- domain randomisation ----

TEST(EnvRandomization, FrictionIsSetOnEveryGeom) {
  Env env(SceneModel(), WithOnly(&RandomizationConfig::friction, {0.3, 0.3}), 12);
  EXPECT_EQ(env.randomization().friction, 0.3);
  for (int g = 0; g < env.model().ngeom; ++g) {
    EXPECT_EQ(env.model().geom_friction[3 * g], 0.3) << "geom " << g;
  }
  // The shared model the env was made from is untouched.
  EXPECT_EQ(SceneModel().geom_friction[0], 1.0);
}

TEST(EnvRandomization, RestitutionSetsTheMatchingContactDampingRatio) {
  Env env(SceneModel(), WithOnly(&RandomizationConfig::restitution, {0.5, 0.5}), 13);
  EXPECT_EQ(env.randomization().restitution, 0.5);
  for (int g = 0; g < env.model().ngeom; ++g) {
    // A mass-spring-damper with damping ratio z bounces back with e = exp(-z pi / sqrt(1 - z^2)).
    const double z = env.model().geom_solref[mjNREF * g + 1];
    EXPECT_NEAR(std::exp(-z * M_PI / std::sqrt(1.0 - z * z)), 0.5, 1e-12) << "geom " << g;
  }
  // No restitution is critical damping.
  Env plain(SceneModel(), DeterministicConfig(), 13);
  for (int g = 0; g < plain.model().ngeom; ++g) {
    EXPECT_EQ(plain.model().geom_solref[mjNREF * g + 1], 1.0);
  }
}

TEST(EnvRandomization, BaseMassOffsetAddsToTheTrunkOnly) {
  Env env(SceneModel(), WithOnly(&RandomizationConfig::base_mass_offset, {1.0, 1.0}), 14);
  EXPECT_EQ(env.randomization().base_mass_offset, 1.0);
  const mjModel& m = env.model();
  const int trunk = env.index().trunk_body;
  EXPECT_NEAR(mj_getTotalmass(&m), a1::kTotalMass + 1.0, 1e-9);
  EXPECT_NEAR(m.body_mass[trunk], 7.0, 1e-12);
  // The inertia grows with the mass (7/6), and derived constants were recomputed.
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(m.body_inertia[3 * trunk + k], SceneModel().body_inertia[3 * trunk + k] * 7.0 / 6.0,
                1e-15);
  }
  EXPECT_NEAR(m.body_subtreemass[0], a1::kTotalMass + 1.0, 1e-9);
  EXPECT_EQ(m.body_mass[mj_name2id(&m, mjOBJ_BODY, "FR_calf")], 0.151);  // legs as they were
}

TEST(EnvRandomization, LinkMassScaleScalesEveryLegLink) {
  Env env(SceneModel(), WithOnly(&RandomizationConfig::link_mass_scale, {2.0, 2.0}), 15);
  EXPECT_EQ(env.randomization().link_mass_scale, 2.0);
  const mjModel& m = env.model();
  const double trunk_mass = 6.0;
  EXPECT_NEAR(mj_getTotalmass(&m), trunk_mass + 2.0 * (a1::kTotalMass - trunk_mass), 1e-9);
  EXPECT_NEAR(m.body_subtreemass[0], trunk_mass + 2.0 * (a1::kTotalMass - trunk_mass), 1e-9);
  const int thigh = mj_name2id(&m, mjOBJ_BODY, "RL_thigh");
  EXPECT_NEAR(m.body_mass[thigh], 2.0 * 0.888, 1e-12);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(m.body_inertia[3 * thigh + k], 2.0 * SceneModel().body_inertia[3 * thigh + k],
                1e-15);
  }
  EXPECT_EQ(m.body_mass[env.index().trunk_body], trunk_mass);
}

TEST(EnvRandomization, DrawsStayInTheirRangesAndVary) {
  const EnvConfig config;  // every randomisation on, with the default ranges
  const RandomizationConfig& r = config.randomization;
  Env env(SceneModel(), config, 16);
  std::set<double> frictions, masses;
  std::set<int> delays;
  auto inside = [](double x, const RandomRange& range) {
    return x >= range.range.lo && x <= range.range.hi;
  };
  for (int reset = 0; reset < 20; ++reset) {
    env.Reset();
    const EnvRandomization& d = env.randomization();
    EXPECT_TRUE(inside(d.friction, r.friction)) << d.friction;
    EXPECT_TRUE(inside(d.restitution, r.restitution)) << d.restitution;
    EXPECT_TRUE(inside(d.base_mass_offset, r.base_mass_offset)) << d.base_mass_offset;
    EXPECT_TRUE(inside(d.link_mass_scale, r.link_mass_scale)) << d.link_mass_scale;
    for (double s : d.motor_strength) EXPECT_TRUE(inside(s, r.motor_strength)) << s;
    EXPECT_TRUE(d.action_delay == 0 || d.action_delay == 1) << d.action_delay;
    // What is reported is what the model got.
    EXPECT_EQ(env.model().geom_friction[0], d.friction);
    frictions.insert(d.friction);
    masses.insert(mj_getTotalmass(&env.model()));
    delays.insert(d.action_delay);
  }
  EXPECT_GT(frictions.size(), 10u);
  EXPECT_GT(masses.size(), 10u);
  EXPECT_EQ(delays.size(), 2u);
}

// Twin envs, one pushed: a push rewrites the base's world-frame horizontal velocity after the
// physics, so everything else stays identical. 0.02 s pushes at every control step, 0.06 s at
// every third.
TEST(EnvRandomization, PushSetsHorizontalBaseVelocityEveryInterval) {
  for (const auto& [interval_s, push_step] : {std::pair{0.02, 1}, std::pair{0.06, 3}}) {
    SCOPED_TRACE(testing::Message() << "interval_s " << interval_s);
    EnvConfig pushed_config = DeterministicConfig();
    pushed_config.randomization.push.enabled = true;
    pushed_config.randomization.push.interval_s = interval_s;
    pushed_config.randomization.push.max_velocity = 1.0;
    Env pushed(SceneModel(), pushed_config, 17);
    Env calm(SceneModel(), DeterministicConfig(), 17);
    const int root = pushed.index().root_qvel;
    const Action zero = Filled(0.0f);
    for (int step = 1; step < push_step; ++step) {
      pushed.Step(zero.data());
      calm.Step(zero.data());
      ExpectSameState(SceneModel(), pushed.data(), calm.data(), 0.0);
    }
    pushed.Step(zero.data());
    calm.Step(zero.data());
    for (int i = 0; i < SceneModel().nq; ++i) EXPECT_EQ(pushed.data().qpos[i], calm.data().qpos[i]);
    for (int k = 2; k < 6; ++k) EXPECT_EQ(pushed.data().qvel[root + k], calm.data().qvel[root + k]);
    // The state reports the pushed velocity: rotate the body-frame one back to the world.
    const RobotState& s = pushed.state();
    const Eigen::Vector3d world = s.base_orientation * s.base_linear_velocity;
    for (int k = 0; k < 2; ++k) {
      EXPECT_NEAR(world[k], pushed.data().qvel[root + k], 1e-12);
      EXPECT_LE(std::abs(world[k]), 1.0);
      EXPECT_NE(pushed.data().qvel[root + k], calm.data().qvel[root + k]);
    }
  }
}

// Peak arena use seen in an mjData, kept across resets (mj_resetData clears the statistics).
struct ArenaUse {
  int contacts = 0, constraints = 0, stack = 0, full_warnings = 0;
  void Record(const mjData& d) {
    contacts = std::max(contacts, d.maxuse_con);
    constraints = std::max(constraints, d.maxuse_efc);
    stack = std::max(stack, d.maxuse_stack);
    full_warnings += d.warning[mjWARN_CONTACTFULL].number + d.warning[mjWARN_CNSTRFULL].number;
  }
};

// The arena sizes in a1.xml (nconmax, njmax, nstack) are kept small for speed; this holds them
// to a rough worst case: random large actions with full randomisation, falls included, then the
// densest contact found by hand, the robot flat on its belly with its legs splayed.
TEST(Env, ArenaHasHeadroomUnderRandomActionsAndFalls) {
  Env env(SceneModel(), EnvConfig{}, 18);
  ArenaUse use;
  Rng rng(18);
  Action action;
  int falls = 0;
  for (int t = 0; t < 400; ++t) {
    for (float& a : action) a = static_cast<float>(3.0 * Uniform(rng, -1.0, 1.0));
    const Termination ending = env.Step(action.data());
    ASSERT_NE(ending, Termination::kPhysics) << "step " << t;
    if (ending != Termination::kNone) {
      use.Record(env.data());
      falls += IsFailure(ending);
      env.Reset();
    }
  }
  use.Record(env.data());
  EXPECT_GT(falls, 0) << "the random phase should include falls";

  a1::JointArray<double> splayed;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    const int leg = j / a1::kJointsPerLeg, part = j % a1::kJointsPerLeg;
    const bool right = leg % 2 == 0;  // right legs (FR, RR) spread outward at negative hip angles
    splayed[j] = part == 0 ? (right ? -0.8 : 0.8) : (part == 1 ? 1.2 : -0.95);
  }
  for (int j = 0; j < a1::kNumJoints; ++j) env.data().qpos[env.index().qpos[j]] = splayed[j];
  PoseBase(env, 0.1);
  const Action hold = HoldPose(splayed);
  for (int t = 0; t < 50; ++t) env.Step(hold.data());  // lying there: no reset on purpose
  use.Record(env.data());

  const mjModel& m = env.model();
  EXPECT_GT(use.contacts, 4) << "the belly flop should touch with more than the feet";
  EXPECT_LT(use.contacts, m.nconmax);
  EXPECT_LT(use.constraints, m.njmax);
  EXPECT_LT(use.stack, env.data().nstack / 2);
  EXPECT_EQ(use.full_warnings, 0);
  RecordProperty("max_contacts", use.contacts);
  RecordProperty("max_constraints", use.constraints);
  RecordProperty("max_stack", use.stack);
}

// ---- model index ----

TEST(EnvModel, IndexClassifiesEveryGeomByBodyAndLeg) {
  const A1ModelIndex index = A1ModelIndex::Find(SceneModel());
  const mjModel& m = SceneModel();
  EXPECT_EQ(index.geom_role[mj_name2id(&m, mjOBJ_GEOM, "floor")], GeomRole::kFloor);
  EXPECT_EQ(index.geom_role[mj_name2id(&m, mjOBJ_GEOM, "trunk")], GeomRole::kTrunk);
  const std::pair<const char*, GeomRole> parts[] = {{"_hip", GeomRole::kHip},
                                                    {"_thigh", GeomRole::kThigh},
                                                    {"_calf", GeomRole::kCalf},
                                                    {"_foot", GeomRole::kFoot}};
  for (int leg = 0; leg < a1::kNumLegs; ++leg) {
    for (const auto& [suffix, role] : parts) {
      const std::string name = std::string(a1::kLegNames[leg]) + suffix;
      const int g = mj_name2id(&m, mjOBJ_GEOM, name.c_str());
      ASSERT_GE(g, 0) << name;
      EXPECT_EQ(index.geom_role[g], role) << name;
      EXPECT_EQ(index.geom_leg[g], leg) << name;
    }
    EXPECT_EQ(index.foot_geom[leg], mj_name2id(&m, mjOBJ_GEOM, a1::kFootNames[leg]));
  }
  EXPECT_EQ(m.ngeom, 2 + 4 * a1::kNumLegs);  // floor, trunk, and four geoms a leg: all named above
}

// ---- bad input ----

TEST(EnvModel, MissingFileIsNamed) {
  EXPECT_THAT(InputErrorMessage([] { LoadMjModel("does/not/exist.xml"); }),
              HasSubstr("does/not/exist.xml"));
}

TEST(EnvModel, MalformedXmlNamesFileAndQuotesMuJoCo) {
  const TempFile file(".xml", "<mujoco model=\"broken\">\n  <worldbody>\n</mujoco>\n");
  char error[1024] = "";
  mjModel* direct = mj_loadXML(file.path().c_str(), nullptr, error, sizeof(error));
  ASSERT_EQ(direct, nullptr) << "the file was meant to be malformed";
  ASSERT_GT(std::strlen(error), 0u);
  EXPECT_THAT(InputErrorMessage([&] { LoadMjModel(file.path()); }),
              AllOf(HasSubstr(file.path()), HasSubstr(error)));
}

TEST(EnvModel, TimestepOtherThanThePhysicsStepIsRejected) {
  const MjModelPtr model = CopyMjModel(SceneModel());
  model->opt.timestep = 0.002;
  EXPECT_THAT(InputErrorMessage([&] { Env env(*model, DeterministicConfig(), 1); }),
              AllOf(HasSubstr("timestep"), HasSubstr("0.002"), HasSubstr("0.005")));
}

TEST(EnvModel, IncompleteA1IsRejectedNamingWhatIsMissing) {
  const TempFile no_joints(
      ".xml",
      "<mujoco><worldbody><body name=\"trunk\"><freejoint/>"
      "<geom type=\"box\" size=\"0.1 0.1 0.05\"/></body></worldbody></mujoco>\n");
  const MjModelPtr model = LoadMjModel(no_joints.path());
  EXPECT_THAT(InputErrorMessage([&] { A1ModelIndex::Find(*model); }), HasSubstr("FR_hip_joint"));

  const TempFile fixed_trunk(
      ".xml",
      "<mujoco><worldbody><body name=\"trunk\">"
      "<geom type=\"box\" size=\"0.1 0.1 0.05\"/></body></worldbody></mujoco>\n");
  const MjModelPtr fixed = LoadMjModel(fixed_trunk.path());
  EXPECT_THAT(InputErrorMessage([&] { A1ModelIndex::Find(*fixed); }),
              AllOf(HasSubstr("trunk"), HasSubstr("free joint")));
}

TEST(EnvModel, ModelWithoutTheA1IsRejectedNamingTheTrunk) {
  const TempFile file(".xml",
                      "<mujoco><worldbody><geom name=\"floor\" type=\"plane\" size=\"0 0 0.05\"/>"
                      "</worldbody></mujoco>\n");
  const MjModelPtr model = LoadMjModel(file.path());
  EXPECT_THAT(InputErrorMessage([&] { Env env(*model, DeterministicConfig(), 1); }),
              HasSubstr("trunk"));
}

}  // namespace
}  // namespace flsd
