#pragma once
// The skill library's format: the metadata fields that are facts of this robot and this build
// (joint order, observation layout and scales, action scale and default pose, PD gains, control
// period, limits), listed once. `flsd export` writes each as it is; SkillLibrary::Load checks each
// against it and names the first that differs. What a library holds of its own at the top level
// (LibraryValues) and per skill (SkillDescriptor) is one field list each, which export.cc writes
// and skill_library.cc reads; its networks, training and evaluation are written by export.cc.

#include <string>
#include <vector>

#include "robot/a1.h"
#include "robot/observation.h"
#include "robot/target_filter.h"

namespace flsd {

inline constexpr const char* kSkillLibraryFormat = "flsd-skill-library";  // the safetensors "format" entry
// Version 2 holds one or more skill policies (`flsd compose-library` joins libraries); version 1,
// one policy, is still read.
inline constexpr int kSkillLibraryVersion = 2;

inline constexpr int kMaxSkills = 1000000;  // per library and per policy

// Policy P's tensors: layer<l>.{weight,bias} and normalizer.{mean,std} under this prefix.
inline std::string PolicyTensorPrefix(int policy) { return "policies." + std::to_string(policy) + "."; }

// A library's own top-level values. Visit calls v(pointer, field, required, min, max); a value
// that is not required may be absent from older libraries and keeps its default: one from before
// the target filter ran without one, one from before the second-order filter ran the first-order.
struct LibraryValues {
  int num_skills = 0;
  double action_filter_hz = 0.0;  // the target filter's cutoff; 0: none
  int action_filter_order = 1;
  template <class V>
  void Visit(V&& v) {
    v("/num_skills", num_skills, true, 1.0, kMaxSkills);
    v("/action/filter_hz", action_filter_hz, false, 0.0, TargetFilter::kMaxCutoffHz);
    v("/action/filter_order", action_filter_order, false, 1.0, 2.0);
  }
};

// The paper's survival bar, "a survival time exceeding 500 steps" (10 s): the coverage metric
// counts the skills that pass it, the shipping bar and the nearest-skill selector require it.
inline constexpr int kSurvivalSteps = 500;
inline bool Survives(int survival_steps) { return survival_steps > kSurvivalSteps; }
// A skill's earliest fall no later than this many steps makes it undependable: any fall.
inline constexpr int kAnyFall = 2147483647;

// Calls v(pointer, value) for every fact, with value an int, a double, a std::string, a
// std::vector<double> or a std::vector<std::string>. A policy's o^p ends with a one-hot over its
// own skills: /policies/P/num_skills of them (VisitPolicyFacts).
template <class V>
void VisitLibraryFacts(V&& v) {
  v("/format", std::string(kSkillLibraryFormat));
  v("/format_version", kSkillLibraryVersion);
  v("/robot", std::string("unitree_a1"));
  v("/joint_names", std::vector<std::string>(a1::kJointNames.begin(), a1::kJointNames.end()));
  for (size_t s = 0; s < kMotionObsLayout.size(); ++s) {
    const std::string at = "/observation/motion/" + std::to_string(s);
    v(at + "/name", std::string(kMotionObsLayout[s].name));
    v(at + "/offset", kMotionObsLayout[s].offset);
    v(at + "/size", kMotionObsLayout[s].size);
    v(at + "/scale", kMotionObsLayout[s].scale);
  }
  v("/observation/motion_size", kMotionObsSize);
  v("/observation/policy/motion", kMotionObsSize);
  v("/observation/policy/previous_action", kActionSize);
  v("/observation/normalized_size", kMotionObsSize + kActionSize);
  v("/action/size", kActionSize);
  v("/action/scale", a1::kActionScale);
  v("/action/clip", a1::kActionClip);
  v("/action/default_joint_positions", std::vector<double>(a1::kDefaultJointPos.begin(), a1::kDefaultJointPos.end()));
  v("/control/kp", a1::kKp);
  v("/control/kd", a1::kKd);
  v("/control/control_dt", a1::kControlDt);
  v("/control/physics_dt", a1::kPhysicsDt);
  v("/control/decimation", a1::kDecimation);
  v("/limits/torque", a1::kTorqueLimit);
  v("/limits/joint_velocity", a1::kJointVelocityLimit);
  std::vector<double> joint_min, joint_max;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    joint_min.push_back(a1::JointMin(j));
    joint_max.push_back(a1::JointMax(j));
  }
  v("/limits/joint_min", joint_min);
  v("/limits/joint_max", joint_max);
}

// The facts of policy P of a library with its `num_skills`, at /policies/P.
template <class V>
void VisitPolicyFacts(V&& v, int policy, int num_skills) {
  const std::string at = "/policies/" + std::to_string(policy);
  v(at + "/activation", std::string("elu"));
  v(at + "/num_skills", num_skills);
  v(at + "/observation_size", PolicyObservationSize(num_skills));
}

}  // namespace flsd
