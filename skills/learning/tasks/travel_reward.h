#pragma once
// A deviation from the paper, off unless `travel.weight` > 0: each skill may be given one of the
// library bar's six directions (evaluation/library_bar.h), or told to stand still, and is then
// paid, beside the discriminator's reward, for travelling that way in its own frame. The mutual-information reward
// alone is met by any set of distinguishable behaviours, and every seed trained on it so far found
// one longitudinal gait varied by speed and turn rate; this names the directions a library needs
// and leaves how each skill moves, and the skills without a direction, to the discriminator.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/config.h"
#include "robot/mirror.h"
#include "skills/learning/evaluation/library_bar.h"

namespace flsd {

// The pay is legged_gym's velocity-tracking kernel with a fixed command per skill:
// weight * exp(-|v - target|^2 / tolerance^2), v the skill's velocity in its own frame and target
// `speed` along its direction, turning counted in metres by turn_scale. It is positive everywhere
// and flat about zero across the direction, so a skill that explores is not punished for it.
struct TravelConfig {
  double weight = 0.0;       // pay per step on target, in the units of log q(k | o^d); 0: off
  double speed = 0.5;        // m/s along the direction (turns: speed / turn_scale rad/s)
  double turn_scale = 0.4;   // m/rad: a turn of 1 rad/s counts as 0.4 m/s, as the bar's 1.0 rad/s to its 0.4 m/s
  double tolerance = 0.5;    // m/s: legged_gym's tracking_sigma 0.25 is this squared
  // One entry per skill: a direction's name (library_bar.h's kDirectionNames), "still" or "none".
  std::vector<std::string> directions;
  // With constraint terminations: hold the skills paid for a direction to the constraints'
  // min_moving_height at any speed. Otherwise the height constraint begins only once a robot
  // travels or turns, and a turn skill can crouch under moving_yaw_rate, out of its reach.
  bool upright = false;
  // With upright: the still skills too. Left low, a still skill crouched under the height the
  // walks keep and fell to pushes the walks took.
  bool upright_still = false;
  // With constraint terminations, m/s (0: off): each step's pay is multiplied by
  // exp(-(s / slip_tolerance)^2), s how much faster than the constraint's slip_speed the step's
  // fastest stance foot slid, so that a skill is paid for walking its way, not for skating it.
  double slip_tolerance = 0.0;

  bool enabled() const { return weight > 0.0; }
  template <class V>
  void Visit(V& v) {
    v("weight", weight, Bounds<double>{0.0, 1000.0});
    v("speed", speed, Bounds<double>{1e-3, 100.0});
    v("turn_scale", turn_scale, Bounds<double>{0.0, 100.0});
    v("tolerance", tolerance, Bounds<double>{1e-3, 100.0});
    v("directions", directions);
    v("upright", upright);
    v("upright_still", upright_still);
    v("slip_tolerance", slip_tolerance, Bounds<double>{0.0, 100.0});
  }
};

// What a skill is paid for: going one of the bar's directions, or standing still. A library
// needs a still skill as much as the directions: skilld brakes a walk with it before the stand's
// targets take the legs (a stand that catches a walk mid-stride can throw the robot).
struct TravelTarget {
  bool still = false;
  Direction direction = Direction::kForward;  // unless still

  static TravelTarget Still() { return {true, Direction::kForward}; }
  static TravelTarget Going(Direction d) { return {false, d}; }
  bool operator==(const TravelTarget& o) const { return still == o.still && (still || direction == o.direction); }
  bool operator!=(const TravelTarget& o) const { return !(*this == o); }
};

// The direction a skill's mirror image goes: left and right swap, as do the turns.
Direction MirrorImage(Direction direction);
TravelTarget MirrorImage(const TravelTarget& target);

using SkillTravelTargets = std::vector<std::optional<TravelTarget>>;  // per skill; nullopt: "none"

// Each skill's target. Throws InputError naming the entry unless there is one per skill, each a
// direction's name, "still" or "none".
SkillTravelTargets ParseSkillTravelTargets(const TravelConfig& config, int num_skills);
// Under mirror symmetry, skill k's mirror image is a sample of its pair's: throws InputError naming
// the entry unless every pair goes mirror-image ways (a self-paired skill forward, backward, still
// or nowhere), so that a sample and its mirror image earn the same.
void CheckMirrorImages(const SkillTravelTargets& targets, const mirror::SkillPairing& pairing);

// The pay for one step of a skill with `target`, given its velocity in the skill's own frame
// (x forward and y left as the robot faced when the skill began, m/s; yaw rate, rad/s).
double TravelReward(const TravelTarget& target, const std::array<double, 3>& skill_frame_velocity,
                    const TravelConfig& config);
// The share of that pay a step keeps whose fastest stance foot slid `slip_excess` m/s faster than
// the slip constraint allows (negative: within it): 1 within it, or with slip_tolerance 0.
double TravelSlipShare(double slip_excess, const TravelConfig& config);

}  // namespace flsd
