#include "skills/learning/networks/motion_streams.h"

#include <algorithm>

#include "core/check.h"

namespace flsd {

MotionStreams::MotionStreams(int num_envs, int steps, int window)
    : num_envs_(num_envs), window_(window), streams_(num_envs), local_ends_(steps * num_envs, -1) {
  FLSD_DEMAND(num_envs >= 1 && steps >= 1 && window >= 1);
}

void MotionStreams::Restart(int env, const float* frame) {
  std::vector<float>& stream = streams_[env];
  for (int copy = 0; copy < window_ - 1; ++copy) stream.insert(stream.end(), frame, frame + kMotionObsSize);
}

void MotionStreams::Push(int env, int step, const float* frame) {
  std::vector<float>& stream = streams_[env];
  stream.insert(stream.end(), frame, frame + kMotionObsSize);
  local_ends_[static_cast<size_t>(step) * num_envs_ + env] = static_cast<int64_t>(stream.size() / kMotionObsSize) - 1;
}

void MotionStreams::BeginRollout() {
  const size_t kept = static_cast<size_t>(window_ - 1) * kMotionObsSize;
  for (std::vector<float>& stream : streams_) {
    FLSD_DEMAND(stream.size() >= kept);  // every env restarted once
    stream.erase(stream.begin(), stream.end() - static_cast<std::ptrdiff_t>(kept));
  }
  std::fill(local_ends_.begin(), local_ends_.end(), -1);
}

MotionStreamFrames MotionStreams::Frames() const {
  std::vector<int64_t> offset(num_envs_ + 1, 0);
  for (int i = 0; i < num_envs_; ++i) offset[i + 1] = offset[i] + streams_[i].size() / kMotionObsSize;
  torch::Tensor frame_major = torch::empty({offset[num_envs_], kMotionObsSize}, torch::kFloat32);
  for (int i = 0; i < num_envs_; ++i) {
    std::copy(streams_[i].begin(), streams_[i].end(), frame_major.data_ptr<float>() + offset[i] * kMotionObsSize);
  }
  MotionStreamFrames out;
  out.frames = frame_major.t().contiguous();
  out.ends = torch::empty({static_cast<int64_t>(local_ends_.size())}, torch::kLong);
  int64_t* ends = out.ends.data_ptr<int64_t>();
  for (size_t k = 0; k < local_ends_.size(); ++k) {
    FLSD_DEMAND(local_ends_[k] >= 0);  // every step of every env pushed
    ends[k] = offset[k % num_envs_] + local_ends_[k];
  }
  return out;
}

torch::Tensor WindowsAlong(const torch::Tensor& frames, const torch::Tensor& ends, int window) {
  const int64_t count = ends.size(0), channels = frames.size(0);
  const torch::Tensor columns = (ends - (window - 1)).unsqueeze(1) + torch::arange(window, torch::kLong);
  return frames.index_select(1, columns.reshape({-1})).view({channels, count, window}).permute({1, 0, 2}).contiguous();
}

}  // namespace flsd
