#pragma once
// N simulated A1s stepped in parallel, with batched outputs in contiguous row-major memory.

#include <memory>
#include <vector>

#include "core/thread_pool.h"
#include "sim/env.h"

namespace flsd {

class VecEnv {
 public:
  // Env i draws from its own random stream StreamSeed(seed, first_env + i), so results depend on
  // the seed alone, not on the thread count; a data-parallel rank holding envs [first_env,
  // first_env + num_envs) of a larger batch draws what those envs would have drawn in one process.
  VecEnv(const EnvConfig& config, int num_envs, uint64_t seed, int num_threads, int first_env = 0);

  int num_envs() const { return static_cast<int>(envs_.size()); }
  int num_threads() const { return pool_.num_threads(); }

  // Resets every env.
  void Reset();

  // Steps every env with its row of `actions` (num_envs x 12). Envs whose episode ended are reset
  // at once; their final state is kept in the terminal_* rows.
  void Step(const float* actions);

  // After Reset or Step, per env (row i):
  const float* motion_obs() const { return motion_obs_.data(); }  // x 33: o^m now
  const float* position() const { return position_.data(); }      // x 3: world base position now
  const unsigned char* foot_contact() const { return foot_contact_.data(); }  // x 4
  // Of the last Step: why env i's episode ended (kNone if it goes on) and, where it ended, the
  // final o^m and position before the reset.
  const Termination* termination() const { return termination_.data(); }
  const float* terminal_motion_obs() const { return terminal_motion_obs_.data(); }
  const float* terminal_position() const { return terminal_position_.data(); }
  // Of the last Step: env i's state at the end of that step (before any reset), and whether a
  // calf struck the floor during it.
  const RobotState& stepped_state(int i) const {
    return termination_[i] == Termination::kNone ? envs_[i].state() : terminal_state_[i];
  }
  bool stepped_calf_contact(int i) const { return stepped_calf_contact_[i] != 0; }
  // Of the last Step, when EnvConfig::constraints is enabled: x kNumConstraints, what env i's step
  // violated (sim/constraints.h), measured before any reset.
  const float* violations() const { return violations_.data(); }

  Env& env(int i) { return envs_[i]; }
  const Env& env(int i) const { return envs_[i]; }
  ThreadPool& pool() { return pool_; }

 private:
  void WriteRow(int i, float* motion_obs, float* position);

  MjModelPtr model_;
  std::vector<Env> envs_;
  ThreadPool pool_;
  std::vector<float> motion_obs_, position_, terminal_motion_obs_, terminal_position_;
  std::vector<unsigned char> foot_contact_, stepped_calf_contact_;
  ConstraintLimits constraints_;
  std::vector<float> violations_;
  std::vector<RobotState> terminal_state_;
  std::vector<Termination> termination_;
};

}  // namespace flsd
