#pragma once
// The motion observations o^m of every env, one stream per env, from which each step's PAE window
// o^H (the H frames up to and including the step's newest) is read in place: consecutive windows
// share H - 1 frames, so they are stored once, and the PAE's first convolution runs once over the
// stream (PeriodicAutoencoderImpl::ManifoldAlong). A new episode starts its stream with H - 1
// copies of its first frame (replicate padding), so a window never mixes two episodes.

#include <torch/torch.h>

#include <vector>

#include "robot/observation.h"

namespace flsd {

// Every env's stream side by side, and where each recorded window ends in it.
struct MotionStreamFrames {
  torch::Tensor frames;  // [kMotionObsSize, L], channel-major, as Conv1d takes it
  torch::Tensor ends;    // [steps * envs] int64: the column of each window's newest frame, step-major
};

class MotionStreams {
 public:
  // Windows of `window` frames for `steps` recorded steps of `num_envs` envs.
  MotionStreams(int num_envs, int steps, int window);

  // A new episode of env `env` whose first frame is `frame` (kMotionObsSize floats).
  void Restart(int env, const float* frame);
  // The episode's next frame: step `step`'s window of env `env` ends with it. Envs may push from
  // different threads; one env only from one.
  void Push(int env, int step, const float* frame);
  // Keeps each env's last H - 1 frames only: call before a rollout's first Push.
  void BeginRollout();
  // The streams and window ends of the steps pushed since BeginRollout (every step pushed).
  MotionStreamFrames Frames() const;

  int window() const { return window_; }

 private:
  int num_envs_, window_;
  std::vector<std::vector<float>> streams_;  // per env, frame-major
  std::vector<int64_t> local_ends_;          // [steps * envs]: frame index within the env's stream
};

// The windows [B, C, H] of `frames` [C, L] that end at columns `ends` [B].
torch::Tensor WindowsAlong(const torch::Tensor& frames, const torch::Tensor& ends, int window);

}  // namespace flsd
