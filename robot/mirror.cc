#include "robot/mirror.h"

#include <string>

#include "core/check.h"

namespace flsd::mirror {
namespace {

// Appends `block` shifted by `offset` to `into`.
void Append(SignedPermutation& into, const SignedPermutation& block) {
  const int offset = into.size();
  for (int i = 0; i < block.size(); ++i) {
    into.source.push_back(offset + block.source[i]);
    into.sign.push_back(block.sign[i]);
  }
}

SignedPermutation Vector(float x, float y, float z) { return {{0, 1, 2}, {x, y, z}}; }

}  // namespace

void SignedPermutation::Apply(const float* in, float* out) const {
  for (int i = 0; i < size(); ++i) out[i] = sign[i] * in[source[i]];
}

SignedPermutation Joints() {
  SignedPermutation p;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    p.source.push_back(Joint(j));
    p.sign.push_back(JointSign(j));
  }
  return p;
}

SignedPermutation MotionObservation() {
  SignedPermutation p;
  Append(p, Vector(1, -1, 1));   // base linear velocity
  Append(p, Vector(-1, 1, -1));  // base angular velocity
  Append(p, Vector(1, -1, 1));   // gravity
  Append(p, Joints());           // joint angles
  Append(p, Joints());           // joint velocities
  FLSD_DEMAND(p.size() == kMotionObsSize);
  return p;
}

SignedPermutation PlanarPosition() { return {{0, 1}, {1, -1}}; }
SignedPermutation VelocityCommand() { return Vector(1, -1, -1); }
SignedPermutation PlanarPose() { return Vector(1, -1, -1); }

SkillPairing::SkillPairing(int num_skills, int self_paired) : num_skills_(num_skills) {
  if (self_paired < 0 || self_paired > num_skills || (num_skills - self_paired) % 2 != 0) {
    throw InputError("self_paired_skills: expected an even number of paired skills, 0 to " +
                     std::to_string(num_skills) + " self-paired of " + std::to_string(num_skills) + ", got " +
                     std::to_string(self_paired));
  }
  pairs_ = (num_skills - self_paired) / 2;
}

int SkillPairing::operator()(int skill) const {
  FLSD_DEMAND(skill >= 0 && skill < num_skills_);
  if (skill >= 2 * pairs_) return skill;
  return skill < pairs_ ? skill + pairs_ : skill - pairs_;
}

SignedPermutation TaskObservation() {
  SignedPermutation p = MotionObservation();
  Append(p, VelocityCommand());
  return p;
}

SignedPermutation PolicyObservation(const SkillPairing& pairing) {
  SignedPermutation p = MotionObservation();
  Append(p, Joints());  // previous action
  SignedPermutation skills;
  for (int k = 0; k < pairing.num_skills(); ++k) {
    skills.source.push_back(pairing(k));
    skills.sign.push_back(1.0f);
  }
  Append(p, skills);
  return p;
}

}  // namespace flsd::mirror
