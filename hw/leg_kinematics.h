#pragma once
// Forward kinematics of the A1's legs, read from robot/a1/a1.urdf with urdfdom: where each foot
// is in the trunk frame for given joint angles, and the Jacobian of that position.

#include <Eigen/Geometry>

#include <array>
#include <string>

#include "robot/a1.h"

namespace flsd::hw {

class LegKinematics {
 public:
  // Reads, for each leg, the hip, thigh and calf joints and the fixed foot joint. Throws
  // InputError naming the file and the missing or ill-formed element.
  static LegKinematics FromUrdf(const std::string& path);

  // The centre of `leg`'s foot in the trunk frame at joint angles q[0..2] (hip, thigh, calf);
  // with `jacobian`, also d(position)/dq (3 x 3).
  Eigen::Vector3d FootPosition(int leg, const double* q, Eigen::Matrix3d* jacobian = nullptr) const;

 private:
  struct Joint {
    Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // in the parent link's frame
    Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  };
  std::array<std::array<Joint, a1::kJointsPerLeg>, a1::kNumLegs> joints_;
  std::array<Eigen::Isometry3d, a1::kNumLegs> foot_;  // foot frame in the calf's frame
};

}  // namespace flsd::hw
