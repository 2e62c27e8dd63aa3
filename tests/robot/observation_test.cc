#include "robot/observation.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testutil::InputErrorMessage;

using MotionObs = std::array<float, kMotionObsSize>;

MotionObs Motion(const RobotState& s) {
  MotionObs out;
  out.fill(NAN);  // so that an entry the builder forgets to write fails every check
  BuildMotionObservation(s, out.data());
  return out;
}

// A state with distinct values everywhere, so a swapped or misplaced entry shows.
RobotState DistinctState(const Eigen::Quaterniond& orientation) {
  RobotState s;
  s.base_orientation = orientation;
  s.base_linear_velocity = {0.5, -0.25, 0.125};
  s.base_angular_velocity = {1.0, -2.0, 4.0};
  for (int j = 0; j < a1::kNumJoints; ++j) {
    s.joint_position[j] = a1::kDefaultJointPos[j] + 0.01 * (j + 1);
    s.joint_velocity[j] = -1.0 + 0.5 * j;
  }
  return s;
}

Eigen::Quaterniond AboutAxis(double angle, const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis));
}

void ExpectGravity(const MotionObs& o, double x, double y, double z) {
  EXPECT_NEAR(o[6], x, 1e-7);
  EXPECT_NEAR(o[7], y, 1e-7);
  EXPECT_NEAR(o[8], z, 1e-7);
}

TEST(MotionObservation, LayoutIsContiguousAndTotals33) {
  int offset = 0;
  for (const ObservationSegment& seg : kMotionObsLayout) {
    EXPECT_EQ(seg.offset, offset) << seg.name;
    offset += seg.size;
  }
  EXPECT_EQ(offset, kMotionObsSize);
  EXPECT_EQ(kMotionObsSize, 33);
  EXPECT_EQ(PolicyObservationSize(8), 33 + 12 + 8);
}

TEST(MotionObservation, ScalesVelocitiesAndJointsAsLeggedGym) {
  // Yawed by 90 deg: velocities are already body-frame, so yaw must not touch them.
  const RobotState s = DistinctState(AboutAxis(M_PI / 2, Eigen::Vector3d::UnitZ()));
  const MotionObs o = Motion(s);
  EXPECT_FLOAT_EQ(o[0], 1.0f);       // 2.0 x 0.5
  EXPECT_FLOAT_EQ(o[1], -0.5f);      // 2.0 x -0.25
  EXPECT_FLOAT_EQ(o[2], 0.25f);      // 2.0 x 0.125
  EXPECT_FLOAT_EQ(o[3], 0.25f);      // 0.25 x 1
  EXPECT_FLOAT_EQ(o[4], -0.5f);      // 0.25 x -2
  EXPECT_FLOAT_EQ(o[5], 1.0f);       // 0.25 x 4
  ExpectGravity(o, 0.0, 0.0, -1.0);  // yaw leaves gravity straight down the body z axis
  for (int j = 0; j < a1::kNumJoints; ++j) {
    EXPECT_NEAR(o[9 + j], 0.01 * (j + 1), 1e-6) << a1::kJointNames[j];
    EXPECT_FLOAT_EQ(o[21 + j], static_cast<float>(0.05 * (-1.0 + 0.5 * j))) << a1::kJointNames[j];
  }
}

TEST(MotionObservation, ProjectedGravityFollowsRollAndPitch) {
  // Identity: g_body = (0, 0, -1).
  ExpectGravity(Motion(DistinctState(Eigen::Quaterniond::Identity())), 0.0, 0.0, -1.0);
  // Roll +90 deg about x: the body y axis points up, so gravity is along -y in the body.
  ExpectGravity(Motion(DistinctState(AboutAxis(M_PI / 2, Eigen::Vector3d::UnitX()))), 0.0, -1.0,
                0.0);
  // Roll 0.3 rad: g_body = R^T (0, 0, -1) = (0, -sin 0.3, -cos 0.3).
  ExpectGravity(Motion(DistinctState(AboutAxis(0.3, Eigen::Vector3d::UnitX()))), 0.0,
                -std::sin(0.3), -std::cos(0.3));
  // Pitch +0.3 rad about y (nose down): g_body = (sin 0.3, 0, -cos 0.3).
  ExpectGravity(Motion(DistinctState(AboutAxis(0.3, Eigen::Vector3d::UnitY()))), std::sin(0.3), 0.0,
                -std::cos(0.3));
  // Upside down (roll 180 deg): gravity along +z of the body.
  ExpectGravity(Motion(DistinctState(AboutAxis(M_PI, Eigen::Vector3d::UnitX()))), 0.0, 0.0, 1.0);
}

TEST(MotionObservation, DefaultPoseAtRestIsZeroExceptGravity) {
  RobotState s;
  s.joint_position = a1::kDefaultJointPos;
  const MotionObs o = Motion(s);
  for (int i = 0; i < kMotionObsSize; ++i) EXPECT_EQ(o[i], i == 8 ? -1.0f : 0.0f) << "entry " << i;
}

TEST(PolicyObservation, ConcatenatesMotionActionAndOneHot) {
  constexpr int kSkills = 5;
  MotionObs motion;
  std::array<float, kActionSize> action;
  for (int i = 0; i < kMotionObsSize; ++i) motion[i] = 0.5f * i;
  for (int i = 0; i < kActionSize; ++i) action[i] = -1.0f - i;
  std::vector<float> out(PolicyObservationSize(kSkills) + 1, NAN);  // one guard entry past the end
  BuildPolicyObservation(motion.data(), action.data(), 3, kSkills, out.data());
  for (int i = 0; i < kMotionObsSize; ++i) EXPECT_EQ(out[i], motion[i]);
  for (int i = 0; i < kActionSize; ++i) EXPECT_EQ(out[kMotionObsSize + i], action[i]);
  for (int k = 0; k < kSkills; ++k) {
    EXPECT_EQ(out[kMotionObsSize + kActionSize + k], k == 3 ? 1.0f : 0.0f);
  }
  EXPECT_TRUE(std::isnan(out.back())) << "wrote past PolicyObservationSize";
}

TEST(PolicyObservation, SkillOutOfRangeNamesTheCount) {
  MotionObs motion{};
  std::array<float, kActionSize> action{};
  std::vector<float> out(PolicyObservationSize(4));
  for (int skill : {-1, 4}) {
    EXPECT_THAT(InputErrorMessage([&] {
                  BuildPolicyObservation(motion.data(), action.data(), skill, 4, out.data());
                }),
                AllOf(HasSubstr("skill " + std::to_string(skill)), HasSubstr("4 skills")));
  }
}

TEST(JointTargets, DefaultPlusQuarterActionClippedAt100) {
  std::array<float, kActionSize> action{};
  action[0] = 1.0f;    // -0.1 + 0.25
  action[1] = -2.0f;   // 0.8 - 0.5
  action[2] = 100.0f;  // at the clip: -1.5 + 25
  action[3] = 250.0f;  // clipped to 100
  action[4] = -1e30f;  // clipped to -100
  const a1::JointArray<double> t = JointTargetsFromAction(action.data());
  EXPECT_DOUBLE_EQ(t[0], 0.15);
  EXPECT_DOUBLE_EQ(t[1], 0.3);
  EXPECT_DOUBLE_EQ(t[2], 23.5);
  EXPECT_DOUBLE_EQ(t[3], 0.1 + 25.0);
  EXPECT_DOUBLE_EQ(t[4], 0.8 - 25.0);
  for (int j = 5; j < a1::kNumJoints; ++j) EXPECT_EQ(t[j], a1::kDefaultJointPos[j]);
}

}  // namespace
}  // namespace flsd
