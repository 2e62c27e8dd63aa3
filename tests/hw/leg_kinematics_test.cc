// Leg kinematics from the URDF: hand-computed foot positions, the Jacobian against finite
// differences, and agreement with MuJoCo's model of the same robot.

#include "hw/leg_kinematics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "sim/env.h"

namespace flsd::hw {
namespace {

class LegKinematicsTest : public ::testing::Test {
 protected:
  LegKinematics k_ = LegKinematics::FromUrdf("robot/a1/a1.urdf");
};

TEST_F(LegKinematicsTest, AStraightLegHangsBelowItsHip) {
  const double q[3] = {0.0, 0.0, 0.0};
  // hip (0.1805, -0.047, 0) + thigh offset (0, -0.0838, 0) + thigh 0.2 + calf 0.2 straight down.
  EXPECT_TRUE(k_.FootPosition(0, q).isApprox(Eigen::Vector3d(0.1805, -0.1308, -0.4), 1e-12));
  EXPECT_TRUE(k_.FootPosition(3, q).isApprox(Eigen::Vector3d(-0.1805, 0.1308, -0.4), 1e-12));  // RL
}

TEST_F(LegKinematicsTest, AThighTurnedAQuarterTurnPointsTheLegBackwards) {
  const double q[3] = {0.0, M_PI / 2, 0.0};
  EXPECT_TRUE(k_.FootPosition(0, q).isApprox(Eigen::Vector3d(0.1805 - 0.4, -0.1308, 0.0), 1e-12));
}

TEST_F(LegKinematicsTest, TheJacobianMatchesFiniteDifferences) {
  for (int leg = 0; leg < a1::kNumLegs; ++leg) {
    double q[3] = {0.2 - 0.1 * leg, 0.7 + 0.05 * leg, -1.4};
    Eigen::Matrix3d jacobian;
    k_.FootPosition(leg, q, &jacobian);
    for (int i = 0; i < 3; ++i) {
      double plus[3] = {q[0], q[1], q[2]}, minus[3] = {q[0], q[1], q[2]};
      plus[i] += 1e-6;
      minus[i] -= 1e-6;
      const Eigen::Vector3d numeric = (k_.FootPosition(leg, plus) - k_.FootPosition(leg, minus)) / 2e-6;
      EXPECT_TRUE(jacobian.col(i).isApprox(numeric, 1e-6)) << "leg " << leg << " joint " << i;
    }
  }
}

TEST_F(LegKinematicsTest, FeetAreWhereMuJoCoPutsThem) {
  EnvConfig config;
  config.randomization.DisableAll();
  config.reset.joint_pos_scale = {0.8, 1.2};  // a posture other than the default
  const MjModelPtr model = LoadMjModel(config.model);
  Env env(*model, config, 5);
  const mjData& d = env.data();
  const RobotState& s = env.state();
  for (int leg = 0; leg < a1::kNumLegs; ++leg) {
    const int g = env.index().foot_geom[leg];
    const Eigen::Vector3d world(d.geom_xpos[3 * g], d.geom_xpos[3 * g + 1], d.geom_xpos[3 * g + 2]);
    const Eigen::Vector3d in_trunk = s.base_orientation.conjugate() * (world - s.base_position);
    const double* q = &s.joint_position[leg * 3];
    EXPECT_LT((k_.FootPosition(leg, q) - in_trunk).norm(), 1e-6) << a1::kLegNames[leg];
  }
}

}  // namespace
}  // namespace flsd::hw
