#pragma once
// What a semi-MDP skill selector remembers between its decisions, kept the same way in training
// (one per env) and in skilld: the skill running, how long since it was switched to and since the
// command changed, and the velocity error averaged over the last window. A selector that sees
// only the present cannot represent a cycle of holds whose mean is the command; with these it can
// see how far the robot's recent mean is from the command and which hold of a cycle it is in.

#include <Eigen/Core>

#include <vector>

namespace flsd {

class SelectorMemory {
 public:
  // Seconds past which the times since a switch and since a new command are not told apart.
  static constexpr double kMaxSeconds = 10.0;
  // The features WriteFeatures writes: the two times, the window's error (vx, vy, wz), then a
  // one-hot of the running skill over num_skills.
  static constexpr int kScalarFeatures = 5;
  static constexpr int FeatureSize(int num_skills) { return kScalarFeatures + num_skills; }

  // window_steps >= 1: control steps the mean velocity is taken over.
  explicit SelectorMemory(int window_steps);

  // A new task. `running`: the skill the robot still runs (-1: none).
  void Reset(int running = -1);
  // One control step: the command it ran under (vx, vy, wz), the skill that acted, and the body
  // velocity it reached, read from o^m (robot/observation.h). A command further than
  // TimeSharingSelector::kNewCommand from the window's starts a new window.
  void Record(const double* command, int skill, const float* motion_obs);

  int running() const { return running_; }
  // The skill that ran before the running one, since the last Reset (-1: none).
  int previous() const { return previous_; }
  double seconds_since_switch() const;
  double seconds_since_command() const;
  // The last command minus the mean (vx, vy, wz) over the window's steps (those since the command
  // changed, at most window_steps); the command itself before any step.
  Eigen::Vector3d WindowError() const;
  // FeatureSize(num_skills) floats; the running skill must be below num_skills.
  void WriteFeatures(int num_skills, float* out) const;
  int window_steps() const { return static_cast<int>(velocities_.size()); }

 private:
  std::vector<Eigen::Vector3d> velocities_;  // ring of the last window_steps
  Eigen::Vector3d sum_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d window_command_ = Eigen::Vector3d::Zero(), last_command_ = Eigen::Vector3d::Zero();
  int count_ = 0, next_ = 0;
  int running_ = -1, previous_ = -1, steps_since_switch_ = 0, steps_since_command_ = 0;
  bool has_command_ = false;
};

}  // namespace flsd
