#pragma once
#include <mujoco/mujoco.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "robot/a1.h"

namespace flsd {

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using MjModelPtr = std::unique_ptr<mjModel, MjModelDeleter>;
using MjDataPtr = std::unique_ptr<mjData, MjDataDeleter>;

// Loads an MJCF file (resolved with ResolveDataPath). Throws InputError naming the file and
// quoting MuJoCo's message when it is missing or malformed.
MjModelPtr LoadMjModel(const std::string& path);
MjModelPtr CopyMjModel(const mjModel& model);

// What a geom is, for contact bookkeeping.
enum class GeomRole : unsigned char { kOther, kFloor, kTrunk, kHip, kThigh, kCalf, kFoot };

// Where the A1's joints, actuators and bodies sit in a MuJoCo model, looked up by name so that
// a1::kJointNames order holds whatever the order in the file.
struct A1ModelIndex {
  a1::JointArray<int> qpos{};      // qpos address of each joint
  a1::JointArray<int> qvel{};      // qvel address of each joint
  a1::JointArray<int> actuator{};  // actuator id driving each joint
  int root_qpos = 0;               // free joint: position (3) then quaternion w, x, y, z (4)
  int root_qvel = 0;               // free joint: world linear velocity (3), body angular (3)
  int trunk_body = 0;
  std::array<int, a1::kNumLegs> foot_geom{};
  std::vector<GeomRole> geom_role;  // indexed by geom id
  std::vector<int> geom_leg;        // leg of a limb or foot geom, -1 otherwise

  // Throws InputError naming the first missing or ill-formed element.
  static A1ModelIndex Find(const mjModel& model);
};

}  // namespace flsd
