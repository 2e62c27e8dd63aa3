// The left-right mirror: its maps are involutions, the observation of a mirrored robot is the
// mirrored observation, skills pair as documented, and MuJoCo's A1 moves as its own mirror image
// (measured: how far a mirrored rollout ends from the mirror image of the original).

#include "robot/mirror.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/check.h"
#include "robot/observation.h"
#include "sim/env.h"

namespace flsd {
namespace {

std::vector<float> Applied(const mirror::SignedPermutation& p, const std::vector<float>& x) {
  std::vector<float> out(x.size());
  p.Apply(x.data(), out.data());
  return out;
}

std::vector<float> Ramp(int n) {
  std::vector<float> x(n);
  for (int i = 0; i < n; ++i) x[i] = 0.1f * (i + 1) * (i % 2 ? -1.0f : 1.0f);
  return x;
}

TEST(Mirror, JointsSwapLeftAndRightAndNegateAbduction) {
  EXPECT_EQ(mirror::Joint(0), 3);  // FR hip <-> FL hip
  EXPECT_EQ(mirror::Joint(5), 2);  // FL calf <-> FR calf
  EXPECT_EQ(mirror::Joint(7), 10);  // RR thigh <-> RL thigh
  EXPECT_EQ(mirror::Joint(9), 6);
  const std::vector<float> q = Ramp(a1::kNumJoints);
  const std::vector<float> m = Applied(mirror::Joints(), q);
  EXPECT_FLOAT_EQ(m[3], -q[0]);
  EXPECT_FLOAT_EQ(m[4], q[1]);
  EXPECT_FLOAT_EQ(m[8], q[11]);
  // The default pose is its own mirror image, so angles relative to it mirror as absolute ones.
  for (int j = 0; j < a1::kNumJoints; ++j) {
    EXPECT_EQ(a1::kDefaultJointPos[mirror::Joint(j)], mirror::JointSign(j) * a1::kDefaultJointPos[j]) << j;
  }
}

TEST(Mirror, APlanarPoseMirrorsItsSidewaysPartAndItsHeading) {
  EXPECT_EQ(Applied(mirror::PlanarPose(), {1.0f, 2.0f, 0.5f}), (std::vector<float>{1.0f, -2.0f, -0.5f}));
}

TEST(Mirror, EveryMapIsItsOwnInverse) {
  const mirror::SkillPairing pairing(16, 4);
  for (const mirror::SignedPermutation& p :
       {mirror::Joints(), mirror::MotionObservation(), mirror::PlanarPosition(), mirror::VelocityCommand(),
        mirror::PlanarPose(), mirror::PolicyObservation(pairing)}) {
    const std::vector<float> x = Ramp(p.size());
    EXPECT_EQ(Applied(p, Applied(p, x)), x);
    EXPECT_NE(Applied(p, x), x);
  }
}

// A robot state and its mirror image: the world mirrored about the x-z plane.
RobotState Mirrored(const RobotState& s) {
  RobotState m = s;
  m.base_position.y() = -s.base_position.y();
  const Eigen::Quaterniond& q = s.base_orientation;
  m.base_orientation = Eigen::Quaterniond(q.w(), -q.x(), q.y(), -q.z());
  m.base_linear_velocity = {s.base_linear_velocity.x(), -s.base_linear_velocity.y(), s.base_linear_velocity.z()};
  m.base_angular_velocity = {-s.base_angular_velocity.x(), s.base_angular_velocity.y(), -s.base_angular_velocity.z()};
  for (int j = 0; j < a1::kNumJoints; ++j) {
    m.joint_position[mirror::Joint(j)] = mirror::JointSign(j) * s.joint_position[j];
    m.joint_velocity[mirror::Joint(j)] = mirror::JointSign(j) * s.joint_velocity[j];
  }
  return m;
}

TEST(Mirror, TheObservationOfAMirroredRobotIsTheMirroredObservation) {
  RobotState s;
  s.base_position = {0.3, 0.2, 0.27};
  s.base_orientation = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                       Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitX());
  s.base_linear_velocity = {0.5, -0.2, 0.05};
  s.base_angular_velocity = {0.3, -0.4, 1.1};
  for (int j = 0; j < a1::kNumJoints; ++j) {
    s.joint_position[j] = a1::kDefaultJointPos[j] + 0.05 * (j - 5);
    s.joint_velocity[j] = 0.7 * (j % 5) - 1.0;
  }
  std::vector<float> obs(kMotionObsSize), mirrored_obs(kMotionObsSize);
  BuildMotionObservation(s, obs.data());
  BuildMotionObservation(Mirrored(s), mirrored_obs.data());
  const std::vector<float> expected = Applied(mirror::MotionObservation(), obs);
  for (int i = 0; i < kMotionObsSize; ++i) EXPECT_NEAR(mirrored_obs[i], expected[i], 1e-6) << i;
}

TEST(Mirror, SkillsPairAsDocumentedAndTheOneHotFollows) {
  const mirror::SkillPairing pairing(16, 4);
  EXPECT_EQ(pairing(0), 6);
  EXPECT_EQ(pairing(6), 0);
  EXPECT_EQ(pairing(5), 11);
  for (int k = 12; k < 16; ++k) EXPECT_EQ(pairing(k), k);
  EXPECT_EQ(mirror::SkillPairing(16, 16)(3), 3);  // no pairs: every skill its own image
  std::vector<float> obs(PolicyObservationSize(16), 0.0f);
  obs[kMotionObsSize + kActionSize + 2] = 1.0f;  // skill 2
  const std::vector<float> m = Applied(mirror::PolicyObservation(pairing), obs);
  EXPECT_EQ(std::find(m.begin(), m.end(), 1.0f) - m.begin(), kMotionObsSize + kActionSize + 8);
  for (int bad : {-1, 3, 17}) {
    EXPECT_THROW(mirror::SkillPairing(16, bad), InputError) << bad;
  }
}

// ---- the model ----

// Puts `env` in `state`'s pose and velocities.
void Place(Env& env, const RobotState& state) {
  mjData& d = env.data();
  const A1ModelIndex& index = env.index();
  mjtNum* q = d.qpos + index.root_qpos;
  const Eigen::Quaterniond& o = state.base_orientation;
  const double pose[7] = {state.base_position.x(), state.base_position.y(), state.base_position.z(), o.w(), o.x(), o.y(), o.z()};
  std::copy(pose, pose + 7, q);
  const Eigen::Vector3d v = o * state.base_linear_velocity;  // the free joint's is in the world frame
  mjtNum* qd = d.qvel + index.root_qvel;
  for (int k = 0; k < 3; ++k) {
    qd[k] = v[k];
    qd[3 + k] = state.base_angular_velocity[k];
  }
  for (int j = 0; j < a1::kNumJoints; ++j) {
    d.qpos[index.qpos[j]] = state.joint_position[j];
    d.qvel[index.qvel[j]] = state.joint_velocity[j];
  }
  env.SyncState();
}

struct MirrorError {
  double position = 0.0;  // m, base
  double yaw = 0.0;       // rad
  double joint = 0.0;     // rad, largest
};

// Steps the nominal A1 for `steps` control steps of a trotting open-loop action from a state,
// and its mirror image with the mirrored actions from the mirrored state; returns how far the
// second ends from the mirror image of the first.
MirrorError MirrorRolloutError(const mjModel& model, int steps) {
  EnvConfig config;
  config.randomization.DisableAll();
  config.episode_steps = 100000;
  config.termination.limits.max_tilt = 3.2;
  config.termination.limits.min_base_height = 0.0;
  Env original(model, config, 1), image(model, config, 1);
  RobotState start = original.state();
  start.base_linear_velocity = {0.3, 0.1, 0.0};
  start.base_angular_velocity = {0.0, 0.0, 0.4};
  Place(original, start);
  Place(image, Mirrored(start));
  const mirror::SignedPermutation joints = mirror::Joints();
  std::array<float, kActionSize> action{}, mirrored{};
  for (int t = 0; t < steps; ++t) {
    for (int j = 0; j < kActionSize; ++j) {
      // Diagonal legs in phase at 2 Hz, the hips swaying: a trot that drifts and turns.
      const int leg = j / 3;
      const double phase = 2.0 * M_PI * 2.0 * t * a1::kControlDt + (leg == 0 || leg == 3 ? 0.0 : M_PI);
      action[j] = static_cast<float>((j % 3 == 0 ? 0.3 : 1.2) * std::sin(phase + 0.2 * j));
    }
    joints.Apply(action.data(), mirrored.data());
    original.Step(action.data());
    image.Step(mirrored.data());
  }
  const RobotState expected = Mirrored(original.state());
  const RobotState& got = image.state();
  MirrorError e;
  e.position = (got.base_position - expected.base_position).norm();
  e.yaw = std::abs(std::remainder(got.Yaw() - expected.Yaw(), 2 * M_PI));
  for (int j = 0; j < a1::kNumJoints; ++j) {
    e.joint = std::max(e.joint, std::abs(got.joint_position[j] - expected.joint_position[j]));
  }
  return e;
}

TEST(Mirror, TheSimulatedA1MovesAsItsOwnMirrorImageButForItsTrunksOffCentreMass) {
  const MjModelPtr model = LoadMjModel("robot/a1/scene.xml");
  // The legs mirror exactly; the trunk's centre of mass sits 4.1 mm left of the midline and its
  // inertia has small products (Unitree's CAD, kept as the real robot is). Made symmetric, the
  // mirrored rollout of 1 s ends where the mirror image of the original does, to MuJoCo's
  // numerical noise between mirrored contact orders.
  MjModelPtr symmetric = CopyMjModel(*model);
  const int trunk = mj_name2id(symmetric.get(), mjOBJ_BODY, "trunk");
  ASSERT_GE(trunk, 0);
  EXPECT_NEAR(symmetric->body_ipos[3 * trunk + 1], 0.0041, 1e-9);
  symmetric->body_ipos[3 * trunk + 1] = 0.0;
  const mjtNum identity[4] = {1, 0, 0, 0};
  std::copy(identity, identity + 4, symmetric->body_iquat + 4 * trunk);
  const MirrorError exact = MirrorRolloutError(*symmetric, 50);
  EXPECT_LT(exact.position, 1e-3);
  EXPECT_LT(exact.yaw, 1e-3);
  EXPECT_LT(exact.joint, 1e-2);
  // As shipped, the offset steers this open-loop (unstable) trot's two images apart: 3.7 cm and
  // 0.066 rad of yaw after the same second, measured. Training keeps the model as the robot is;
  // its closed-loop skills correct for what the mirrored samples leave out.
  const MirrorError shipped = MirrorRolloutError(*model, 50);
  std::printf("mirror error after 1 s: symmetric trunk %.2g m, %.2g rad yaw, %.2g rad joints; "
              "as shipped %.2g m, %.2g rad yaw, %.2g rad joints\n",
              exact.position, exact.yaw, exact.joint, shipped.position, shipped.yaw, shipped.joint);
  EXPECT_GT(shipped.position, 100 * exact.position);
  EXPECT_LT(shipped.position, 0.1);
  EXPECT_LT(shipped.yaw, 0.2);
}

}  // namespace
}  // namespace flsd
