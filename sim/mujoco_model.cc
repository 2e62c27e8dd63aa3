#include "sim/mujoco_model.h"

#include <cstring>

#include "core/check.h"
#include "core/paths.h"

namespace flsd {
namespace {

int RequireId(const mjModel& m, mjtObj type, const std::string& name, const char* what) {
  const int id = mj_name2id(&m, type, name.c_str());
  if (id < 0) throw InputError("A1 model: no " + std::string(what) + " named '" + name + "'");
  return id;
}

bool EndsWith(const char* s, const char* suffix) {
  const size_t n = std::strlen(s), k = std::strlen(suffix);
  return n >= k && std::strcmp(s + n - k, suffix) == 0;
}

}  // namespace

MjModelPtr LoadMjModel(const std::string& path) {
  const std::string resolved = ResolveDataPath(path);
  char error[1024] = "";
  MjModelPtr model(mj_loadXML(resolved.c_str(), nullptr, error, sizeof(error)));
  if (!model) throw InputError(resolved + ": MuJoCo cannot load the model: " + error);
  return model;
}

MjModelPtr CopyMjModel(const mjModel& model) {
  MjModelPtr copy(mj_copyModel(nullptr, &model));
  FLSD_DEMAND(copy != nullptr);
  return copy;
}

A1ModelIndex A1ModelIndex::Find(const mjModel& m) {
  A1ModelIndex index;
  const int root_body = RequireId(m, mjOBJ_BODY, "trunk", "body");
  if (m.body_jntnum[root_body] != 1 || m.jnt_type[m.body_jntadr[root_body]] != mjJNT_FREE) {
    throw InputError("A1 model: body 'trunk' must have exactly one free joint");
  }
  index.trunk_body = root_body;
  index.root_qpos = m.jnt_qposadr[m.body_jntadr[root_body]];
  index.root_qvel = m.jnt_dofadr[m.body_jntadr[root_body]];

  for (int j = 0; j < a1::kNumJoints; ++j) {
    const int joint = RequireId(m, mjOBJ_JOINT, a1::kJointNames[j], "joint");
    if (m.jnt_type[joint] != mjJNT_HINGE) {
      throw InputError(std::string("A1 model: joint '") + a1::kJointNames[j] + "' must be a hinge");
    }
    index.qpos[j] = m.jnt_qposadr[joint];
    index.qvel[j] = m.jnt_dofadr[joint];
    index.actuator[j] = -1;
    for (int a = 0; a < m.nu; ++a) {
      if (m.actuator_trntype[a] == mjTRN_JOINT && m.actuator_trnid[2 * a] == joint) {
        index.actuator[j] = a;
      }
    }
    if (index.actuator[j] < 0) {
      throw InputError(std::string("A1 model: no actuator drives joint '") + a1::kJointNames[j] + "'");
    }
  }

  index.geom_role.assign(m.ngeom, GeomRole::kOther);
  index.geom_leg.assign(m.ngeom, -1);
  for (int g = 0; g < m.ngeom; ++g) {
    const int body = m.geom_bodyid[g];
    const char* body_name = mj_id2name(&m, mjOBJ_BODY, body);
    if (body == 0) {
      index.geom_role[g] = GeomRole::kFloor;
      continue;
    }
    if (body == root_body) {
      index.geom_role[g] = GeomRole::kTrunk;
      continue;
    }
    if (body_name == nullptr) continue;
    for (int leg = 0; leg < a1::kNumLegs; ++leg) {
      if (std::strncmp(body_name, a1::kLegNames[leg], 2) != 0) continue;
      index.geom_leg[g] = leg;
      if (EndsWith(body_name, "_hip")) index.geom_role[g] = GeomRole::kHip;
      if (EndsWith(body_name, "_thigh")) index.geom_role[g] = GeomRole::kThigh;
      if (EndsWith(body_name, "_calf")) index.geom_role[g] = GeomRole::kCalf;
      if (EndsWith(body_name, "_foot")) index.geom_role[g] = GeomRole::kFoot;
    }
  }
  for (int leg = 0; leg < a1::kNumLegs; ++leg) {
    index.foot_geom[leg] = RequireId(m, mjOBJ_GEOM, a1::kFootNames[leg], "geom");
  }
  return index;
}

}  // namespace flsd
