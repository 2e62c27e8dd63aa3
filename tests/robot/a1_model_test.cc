// The A1 is described three times: robot/a1.h (constants the C++ uses), robot/a1/a1.urdf and
// robot/a1/a1.xml (MJCF). These tests hold the three to each other.
//
// Tolerances: names, order, axes and the per-joint limits are compared exactly or to 1e-6 (the
// files write the limits with 6 significant digits, like a1.h); masses, positions and COMs are
// copied from the same numbers and only parsed, so 1e-9; the inertia tensor goes through MuJoCo's
// eigen-decomposition (body_iquat, body_inertia) and back, so 1e-7 (entries are 1e-5 .. 5e-2).

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <urdf_parser/urdf_parser.h>

#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/paths.h"
#include "robot/a1.h"

namespace flsd {
namespace {

constexpr double kLimitTol = 1e-6;
constexpr double kParseTol = 1e-9;
constexpr double kInertiaTol = 1e-7;

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};

class A1ModelTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    char error[1024] = "";
    const std::string mjcf = ResolveDataPath("robot/a1/a1.xml");
    mj_.reset(mj_loadXML(mjcf.c_str(), nullptr, error, sizeof(error)));
    ASSERT_NE(mj_, nullptr) << mjcf << ": " << error;
    urdf_ = urdf::parseURDFFile(ResolveDataPath("robot/a1/a1.urdf"));
    ASSERT_NE(urdf_, nullptr);
  }
  static void TearDownTestSuite() {
    mj_.reset();
    urdf_.reset();
  }

  static const mjModel& mj() { return *mj_; }
  static const urdf::ModelInterface& urdf() { return *urdf_; }

  // Missing elements end the test (GoogleTest reports the exception) rather than index with -1.
  static int BodyId(const std::string& name) { return Require(mjOBJ_BODY, name, "body"); }
  static int JointId(const std::string& name) { return Require(mjOBJ_JOINT, name, "joint"); }
  static urdf::JointConstSharedPtr UrdfJoint(const std::string& name) {
    urdf::JointConstSharedPtr joint = urdf_->getJoint(name);
    if (joint == nullptr) throw std::runtime_error("no URDF joint '" + name + "'");
    return joint;
  }

  static urdf::LinkConstSharedPtr UrdfLink(const std::string& name) {
    urdf::LinkConstSharedPtr link = urdf_->getLink(name);
    if (link == nullptr || link->inertial == nullptr) {
      throw std::runtime_error("no URDF link '" + name + "' with an inertial");
    }
    return link;
  }

  void SetUp() override {
    ASSERT_TRUE(mj_ != nullptr && urdf_ != nullptr) << "the model files did not load";
  }

 private:
  static int Require(mjtObj type, const std::string& name, const char* what) {
    const int id = mj_name2id(mj_.get(), type, name.c_str());
    if (id < 0) throw std::runtime_error("no MuJoCo " + std::string(what) + " '" + name + "'");
    return id;
  }

  static inline std::unique_ptr<mjModel, ModelDeleter> mj_;
  static inline urdf::ModelInterfaceSharedPtr urdf_;
};

// Every link of the leg chain, as named in both files.
std::vector<std::string> LinkNames() {
  std::vector<std::string> names = {"trunk"};
  for (const char* leg : a1::kLegNames) {
    for (const char* part : {"_hip", "_thigh", "_calf", "_foot"}) {
      names.push_back(std::string(leg) + part);
    }
  }
  return names;
}

urdf::Vector3 Vec(const double* v) { return urdf::Vector3(v[0], v[1], v[2]); }

void ExpectNear3(const urdf::Vector3& a, const urdf::Vector3& b, double tol,
                 const std::string& what) {
  EXPECT_NEAR(a.x, b.x, tol) << what << " x";
  EXPECT_NEAR(a.y, b.y, tol) << what << " y";
  EXPECT_NEAR(a.z, b.z, tol) << what << " z";
}

void ExpectIdentityRotation(const urdf::Pose& pose, const std::string& what) {
  double x, y, z, w;
  pose.rotation.getQuaternion(x, y, z, w);
  EXPECT_EQ(std::abs(w), 1.0) << what << " has a rotation; the MJCF assumes none";
}

TEST_F(A1ModelTest, JointAndActuatorOrderIsA1JointNames) {
  // One free joint, then the 12 hinges in a1::kJointNames order, so qpos = [root 7, joints 12].
  ASSERT_EQ(mj().njnt, 1 + a1::kNumJoints);
  ASSERT_EQ(mj().nq, 7 + a1::kNumJoints);
  ASSERT_EQ(mj().nu, a1::kNumJoints);
  EXPECT_EQ(mj().jnt_type[0], mjJNT_FREE);
  for (int j = 0; j < a1::kNumJoints; ++j) {
    const int id = 1 + j;
    EXPECT_STREQ(mj_id2name(&mj(), mjOBJ_JOINT, id), a1::kJointNames[j]);
    EXPECT_EQ(mj().jnt_type[id], mjJNT_HINGE);
    EXPECT_EQ(mj().jnt_qposadr[id], 7 + j);
    EXPECT_EQ(mj().jnt_dofadr[id], 6 + j);
    // Actuator j drives joint j, as a plain torque motor.
    EXPECT_EQ(mj().actuator_trntype[j], mjTRN_JOINT);
    EXPECT_EQ(mj().actuator_trnid[2 * j], id) << "actuator " << j;
    EXPECT_EQ(mj().actuator_gear[6 * j], 1.0);
    // The URDF has the same joint as a revolute one.
    const urdf::JointConstSharedPtr joint = UrdfJoint(a1::kJointNames[j]);
    EXPECT_EQ(joint->type, urdf::Joint::REVOLUTE);
  }
  // The URDF has nothing else but the four fixed foot joints.
  EXPECT_EQ(urdf().joints_.size(), static_cast<size_t>(a1::kNumJoints + a1::kNumLegs));
  for (const char* foot : a1::kFootNames) {
    const urdf::JointConstSharedPtr joint = UrdfJoint(std::string(foot) + "_fixed");
    EXPECT_EQ(joint->type, urdf::Joint::FIXED);
  }
}

TEST_F(A1ModelTest, AxesMatch) {
  for (int j = 0; j < a1::kNumJoints; ++j) {
    const bool hip = j % a1::kJointsPerLeg == 0;
    const urdf::Vector3 expected(hip ? 1.0 : 0.0, hip ? 0.0 : 1.0, 0.0);
    ExpectNear3(Vec(mj().jnt_axis + 3 * JointId(a1::kJointNames[j])), expected, 0.0,
                std::string("MJCF axis of ") + a1::kJointNames[j]);
    ExpectNear3(UrdfJoint(a1::kJointNames[j])->axis, expected, 0.0,
                std::string("URDF axis of ") + a1::kJointNames[j]);
  }
}

TEST_F(A1ModelTest, RangesEffortAndVelocityMatchA1Constants) {
  for (int j = 0; j < a1::kNumJoints; ++j) {
    const std::string name = a1::kJointNames[j];
    const int id = JointId(name);
    EXPECT_TRUE(mj().jnt_limited[id]) << name;
    EXPECT_NEAR(mj().jnt_range[2 * id], a1::JointMin(j), kLimitTol) << name;
    EXPECT_NEAR(mj().jnt_range[2 * id + 1], a1::JointMax(j), kLimitTol) << name;

    const urdf::JointConstSharedPtr joint = UrdfJoint(name);
    ASSERT_NE(joint->limits, nullptr) << name;
    EXPECT_NEAR(joint->limits->lower, a1::JointMin(j), kLimitTol) << name;
    EXPECT_NEAR(joint->limits->upper, a1::JointMax(j), kLimitTol) << name;
    EXPECT_EQ(joint->limits->effort, a1::kTorqueLimit) << name;
    // MJCF has no velocity limit field; the URDF is the only file that states it.
    EXPECT_EQ(joint->limits->velocity, a1::kJointVelocityLimit) << name;

    EXPECT_TRUE(mj().actuator_ctrllimited[j]) << name;
    EXPECT_EQ(mj().actuator_ctrlrange[2 * j], -a1::kTorqueLimit) << name;
    EXPECT_EQ(mj().actuator_ctrlrange[2 * j + 1], a1::kTorqueLimit) << name;
  }
}

TEST_F(A1ModelTest, DefaultPoseIsInsideTheJointRanges) {
  for (int j = 0; j < a1::kNumJoints; ++j) {
    EXPECT_GT(a1::kDefaultJointPos[j], a1::JointMin(j)) << a1::kJointNames[j];
    EXPECT_LT(a1::kDefaultJointPos[j], a1::JointMax(j)) << a1::kJointNames[j];
  }
}

TEST_F(A1ModelTest, TimestepIsThePhysicsStep) { EXPECT_EQ(mj().opt.timestep, a1::kPhysicsDt); }

TEST_F(A1ModelTest, LinkMassesMatchAndSumToTotalMass) {
  // World plus one body per URDF link, and no others.
  EXPECT_EQ(mj().nbody, static_cast<int>(urdf().links_.size()) + 1);
  double urdf_total = 0.0;
  for (const std::string& name : LinkNames()) {
    const urdf::LinkConstSharedPtr link = UrdfLink(name);
    EXPECT_NEAR(mj().body_mass[BodyId(name)], link->inertial->mass, kParseTol) << name;
    urdf_total += link->inertial->mass;
  }
  EXPECT_NEAR(urdf_total, a1::kTotalMass, 1e-6);
  EXPECT_NEAR(mj_getTotalmass(&mj()), a1::kTotalMass, 1e-6);
}

TEST_F(A1ModelTest, JointOriginsMatchBodyPositions) {
  for (const auto& [name, joint] : urdf().joints_) {
    const int child = BodyId(joint->child_link_name);
    const int parent = BodyId(joint->parent_link_name);
    // Same tree: the URDF parent link is the MuJoCo parent body.
    EXPECT_EQ(mj().body_parentid[child], parent) << name;
    ExpectNear3(Vec(mj().body_pos + 3 * child), joint->parent_to_joint_origin_transform.position,
                kParseTol, name + " origin");
    ExpectIdentityRotation(joint->parent_to_joint_origin_transform, name);
    EXPECT_EQ(mj().body_quat[4 * child], 1.0) << name << ": MJCF body is rotated";
    if (joint->type == urdf::Joint::REVOLUTE) {
      // The hinge sits in the child body at its origin, as the URDF joint frame does.
      const int id = JointId(name);
      EXPECT_EQ(mj().jnt_bodyid[id], child) << name;
      ExpectNear3(Vec(mj().jnt_pos + 3 * id), urdf::Vector3(0.0, 0.0, 0.0), 0.0, name + " pos");
    }
  }
}

TEST_F(A1ModelTest, CentresOfMassAndInertiaTensorsMatch) {
  for (const std::string& name : LinkNames()) {
    const int body = BodyId(name);
    const urdf::Inertial& in = *UrdfLink(name)->inertial;
    ExpectNear3(Vec(mj().body_ipos + 3 * body), in.origin.position, kParseTol, name + " COM");
    ExpectIdentityRotation(in.origin, name + " inertial frame");

    // MuJoCo stores principal moments and the frame that holds them; rebuild R diag(I) R^T.
    double rot[9];
    mju_quat2Mat(rot, mj().body_iquat + 4 * body);
    const double* principal = mj().body_inertia + 3 * body;
    double tensor[3][3];
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        tensor[r][c] = 0.0;
        for (int k = 0; k < 3; ++k) tensor[r][c] += rot[3 * r + k] * principal[k] * rot[3 * c + k];
      }
    }
    EXPECT_NEAR(tensor[0][0], in.ixx, kInertiaTol) << name;
    EXPECT_NEAR(tensor[1][1], in.iyy, kInertiaTol) << name;
    EXPECT_NEAR(tensor[2][2], in.izz, kInertiaTol) << name;
    EXPECT_NEAR(tensor[0][1], in.ixy, kInertiaTol) << name;
    EXPECT_NEAR(tensor[0][2], in.ixz, kInertiaTol) << name;
    EXPECT_NEAR(tensor[1][2], in.iyz, kInertiaTol) << name;
  }
}

// The URDF's collision shapes are the MJCF's, with capsules written as cylinders of the same
// radius and segment length; the foot sphere is a1::kFootRadius.
TEST_F(A1ModelTest, CollisionShapesMatch) {
  for (const std::string& name : LinkNames()) {
    const int body = BodyId(name);
    ASSERT_EQ(mj().body_geomnum[body], 1) << name;
    const int g = mj().body_geomadr[body];
    const urdf::LinkConstSharedPtr link = UrdfLink(name);
    ASSERT_NE(link->collision, nullptr) << name;
    ASSERT_EQ(link->collision_array.size(), 1u) << name;
    const urdf::Collision& col = *link->collision;
    ExpectNear3(Vec(mj().geom_pos + 3 * g), col.origin.position, kParseTol, name + " geom centre");
    const double* size = mj().geom_size + 3 * g;
    switch (col.geometry->type) {
      case urdf::Geometry::SPHERE:
        EXPECT_EQ(mj().geom_type[g], mjGEOM_SPHERE) << name;
        EXPECT_NEAR(size[0], static_cast<const urdf::Sphere&>(*col.geometry).radius, kParseTol)
            << name;
        break;
      case urdf::Geometry::BOX: {
        EXPECT_EQ(mj().geom_type[g], mjGEOM_BOX) << name;
        const urdf::Vector3& dim = static_cast<const urdf::Box&>(*col.geometry).dim;
        // MuJoCo sizes a box by its half extents, the URDF by its full ones.
        ExpectNear3(urdf::Vector3(2.0 * size[0], 2.0 * size[1], 2.0 * size[2]), dim, kParseTol,
                    name + " box size");
        break;
      }
      case urdf::Geometry::CYLINDER: {
        EXPECT_EQ(mj().geom_type[g], mjGEOM_CAPSULE) << name;
        const auto& cyl = static_cast<const urdf::Cylinder&>(*col.geometry);
        EXPECT_NEAR(size[0], cyl.radius, kParseTol) << name;
        EXPECT_NEAR(2.0 * size[1], cyl.length, kParseTol) << name;
        // Along the body z axis, either way round.
        double z[3];
        const double unit_z[3] = {0.0, 0.0, 1.0};
        mju_rotVecQuat(z, unit_z, mj().geom_quat + 4 * g);
        EXPECT_NEAR(std::abs(z[2]), 1.0, kParseTol) << name;
        break;
      }
      default:
        ADD_FAILURE() << name << ": unexpected URDF collision geometry";
    }
  }
  for (const char* foot : a1::kFootNames) {
    const int g = mj_name2id(&mj(), mjOBJ_GEOM, foot);
    ASSERT_GE(g, 0) << foot;
    EXPECT_EQ(mj().geom_size[3 * g], a1::kFootRadius) << foot;
  }
}

}  // namespace
}  // namespace flsd
