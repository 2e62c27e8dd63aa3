#include "skills/runtime/selector_memory.h"

#include <algorithm>

#include "core/check.h"
#include "robot/a1.h"
#include "robot/observation.h"
#include "skills/runtime/nearest_skill.h"

namespace flsd {

SelectorMemory::SelectorMemory(int window_steps) {
  if (window_steps < 1) throw InputError("selector memory window: expected at least 1 step, got " + std::to_string(window_steps));
  velocities_.assign(window_steps, Eigen::Vector3d::Zero());
}

void SelectorMemory::Reset(int running) {
  sum_.setZero();
  last_command_.setZero();
  count_ = next_ = 0;
  running_ = running;
  previous_ = -1;
  steps_since_switch_ = steps_since_command_ = 0;
  has_command_ = false;
}

void SelectorMemory::Record(const double* command, int skill, const float* motion_obs) {
  const Eigen::Vector3d asked(command[0], command[1], command[2]);
  last_command_ = asked;
  if (!has_command_ || NearestSkillSelector::Distance(asked, window_command_) > TimeSharingSelector::kNewCommand) {
    window_command_ = asked;
    has_command_ = true;
    sum_.setZero();
    count_ = next_ = steps_since_command_ = 0;
  }
  if (skill != running_) {
    steps_since_switch_ = 0;
    previous_ = running_;
  }
  running_ = skill;
  const ObservationSegment& lin = kMotionObsLayout[0];
  const ObservationSegment& ang = kMotionObsLayout[1];
  const Eigen::Vector3d v(motion_obs[lin.offset] / lin.scale, motion_obs[lin.offset + 1] / lin.scale,
                          motion_obs[ang.offset + 2] / ang.scale);
  const int window = window_steps();
  if (count_ == window) sum_ -= velocities_[next_];
  velocities_[next_] = v;
  sum_ += v;
  next_ = (next_ + 1) % window;
  count_ = std::min(count_ + 1, window);
  ++steps_since_switch_;
  ++steps_since_command_;
}

double SelectorMemory::seconds_since_switch() const {
  return std::min(steps_since_switch_ * a1::kControlDt, kMaxSeconds);
}

double SelectorMemory::seconds_since_command() const {
  return std::min(steps_since_command_ * a1::kControlDt, kMaxSeconds);
}

Eigen::Vector3d SelectorMemory::WindowError() const {
  return count_ == 0 ? last_command_ : Eigen::Vector3d(last_command_ - sum_ / count_);
}

void SelectorMemory::WriteFeatures(int num_skills, float* out) const {
  const Eigen::Vector3d error = WindowError();
  out[0] = static_cast<float>(seconds_since_switch());
  out[1] = static_cast<float>(seconds_since_command());
  for (int a = 0; a < 3; ++a) out[2 + a] = static_cast<float>(error[a]);
  std::fill(out + kScalarFeatures, out + kScalarFeatures + num_skills, 0.0f);
  if (running_ >= 0) {
    FLSD_DEMAND(running_ < num_skills);
    out[kScalarFeatures + running_] = 1.0f;
  }
}

}  // namespace flsd
