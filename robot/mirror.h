#pragma once
// The A1's left-right mirror image: its reflection about the body's sagittal (x-z) plane. The A1
// is built left-right symmetric (the front-back mirror does not hold: every knee points back and
// the front and rear thighs stand at different angles), so a motion and its mirror image are
// equally feasible. Training mirrors its samples with these maps (Mittal et al., "Symmetry
// considerations for learning task symmetric robot policies", ICRA 2024), the skill library
// records which skill is whose mirror image, and the selector mirrors its commands with them.
//
// Every map here is a signed permutation: out[i] = sign[i] * in[source[i]]. Reflecting a vector
// (x, y, z) gives (x, -y, z); an axial vector (angular velocity) gives (-x, y, -z). Joints swap
// FR<->FL and RR<->RL, and the hip abduction angle changes sign (the default pose's abduction is
// antisymmetric, -0.1 right and +0.1 left, so angles relative to it mirror the same way).

#include <vector>

#include "robot/observation.h"

namespace flsd::mirror {

struct SignedPermutation {
  std::vector<int> source;
  std::vector<float> sign;
  int size() const { return static_cast<int>(source.size()); }
  // out[i] = sign[i] * in[source[i]]; in and out must not overlap.
  void Apply(const float* in, float* out) const;
};

// The joint whose mirror image joint j is, and the sign its angle takes.
inline constexpr int Joint(int j) { return (j / a1::kJointsPerLeg ^ 1) * a1::kJointsPerLeg + j % a1::kJointsPerLeg; }
inline constexpr float JointSign(int j) { return j % a1::kJointsPerLeg == 0 ? -1.0f : 1.0f; }

// Joint vectors (actions, angles relative to the default pose, joint velocities, torques).
SignedPermutation Joints();
// o^m (robot/observation.h).
SignedPermutation MotionObservation();
// A point or vector in the world frame's horizontal plane (x, y) -> (x, -y). The robot starts
// every episode at the origin facing +x, so the world frame mirrors as the body does.
SignedPermutation PlanarPosition();
// A velocity command (vx, vy, wz) -> (vx, -vy, -wz).
SignedPermutation VelocityCommand();
// A pose in the horizontal plane (x, y, heading) -> (x, -y, -heading).
SignedPermutation PlanarPose();

// Which skill is the mirror image of which: skills [0, 2P) form the pairs (k, k + P), and the
// rest mirror themselves (a self-paired skill must be its own mirror image: it goes straight or
// turns in place, which is what a selector needs for "forward", "backward" and "stop").
class SkillPairing {
 public:
  // Throws InputError unless 0 <= self_paired <= num_skills and num_skills - self_paired is even.
  SkillPairing(int num_skills, int self_paired);
  int operator()(int skill) const;
  int num_skills() const { return num_skills_; }
  int self_paired() const { return num_skills_ - 2 * pairs_; }

 private:
  int num_skills_, pairs_;
};

// o^c = [o^m, velocity command] (robot/observation.h).
SignedPermutation TaskObservation();

// o^p = [o^m, previous action, one-hot skill]: the skill's one-hot moves to its mirror image.
SignedPermutation PolicyObservation(const SkillPairing& pairing);

}  // namespace flsd::mirror
