#include "hw/leg_kinematics.h"

#include <urdf_parser/urdf_parser.h>

#include "core/check.h"
#include "core/paths.h"

namespace flsd::hw {
namespace {

Eigen::Isometry3d ToIsometry(const urdf::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  double x, y, z, w;
  pose.rotation.getQuaternion(x, y, z, w);
  t.linear() = Eigen::Quaterniond(w, x, y, z).toRotationMatrix();
  t.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return t;
}

}  // namespace

LegKinematics LegKinematics::FromUrdf(const std::string& path) {
  const std::string file = ResolveDataPath(path);
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(file);
  if (!model) throw InputError(file + ": not a valid URDF");
  LegKinematics k;
  for (int leg = 0; leg < a1::kNumLegs; ++leg) {
    for (int i = 0; i < a1::kJointsPerLeg; ++i) {
      const char* name = a1::kJointNames[leg * a1::kJointsPerLeg + i];
      const urdf::JointConstSharedPtr joint = model->getJoint(name);
      if (!joint) throw InputError(file + ": no joint '" + name + "'");
      k.joints_[leg][i].origin = ToIsometry(joint->parent_to_joint_origin_transform);
      k.joints_[leg][i].axis = Eigen::Vector3d(joint->axis.x, joint->axis.y, joint->axis.z).normalized();
    }
    const std::string foot_joint = std::string(a1::kLegNames[leg]) + "_foot_fixed";
    const urdf::JointConstSharedPtr foot = model->getJoint(foot_joint);
    if (!foot) throw InputError(file + ": no joint '" + foot_joint + "'");
    k.foot_[leg] = ToIsometry(foot->parent_to_joint_origin_transform);
  }
  return k;
}

Eigen::Vector3d LegKinematics::FootPosition(int leg, const double* q, Eigen::Matrix3d* jacobian) const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  std::array<Eigen::Vector3d, a1::kJointsPerLeg> axis_in_trunk, joint_in_trunk;
  for (int i = 0; i < a1::kJointsPerLeg; ++i) {
    const Joint& j = joints_[leg][i];
    t = t * j.origin;
    axis_in_trunk[i] = t.linear() * j.axis;
    joint_in_trunk[i] = t.translation();
    t = t * Eigen::AngleAxisd(q[i], j.axis);
  }
  const Eigen::Vector3d foot = (t * foot_[leg]).translation();
  if (jacobian != nullptr) {
    // A revolute joint moves the foot at axis x (foot - joint) per radian.
    for (int i = 0; i < a1::kJointsPerLeg; ++i) jacobian->col(i) = axis_in_trunk[i].cross(foot - joint_in_trunk[i]);
  }
  return foot;
}

}  // namespace flsd::hw
