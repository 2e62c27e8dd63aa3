#include "skills/learning/networks/motion_streams.h"

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "robot/observation.h"

namespace flsd {
namespace {

using Frame = std::array<float, kMotionObsSize>;

// Frame j holds 100 j + c in channel c, so every (frame, channel) value is distinct.
Frame FrameNo(int j) {
  Frame f;
  for (int c = 0; c < kMotionObsSize; ++c) f[c] = static_cast<float>(100 * j + c);
  return f;
}

// Checks that time step t of window [33, H] holds frame frames[t].
void ExpectWindowOfFrames(const torch::Tensor& window, const std::vector<int>& frames) {
  const int h = static_cast<int>(frames.size());
  ASSERT_EQ(window.sizes(), (std::vector<int64_t>{kMotionObsSize, h}));
  for (int t = 0; t < h; ++t) {
    for (int c = 0; c < kMotionObsSize; ++c) {
      ASSERT_EQ(window[c][t].item<float>(), FrameNo(frames[t])[c]) << "channel " << c << ", time " << t;
    }
  }
}

// The window of env `env` at step `step`, read from the streams.
torch::Tensor WindowAt(const MotionStreams& streams, int envs, int step, int env) {
  const MotionStreamFrames f = streams.Frames();
  return WindowsAlong(f.frames, f.ends.slice(0, step * envs + env, step * envs + env + 1), streams.window())[0];
}

TEST(MotionStreams, RestartReplicatesTheFirstFrame) {
  MotionStreams streams(1, 1, 5);
  streams.Restart(0, FrameNo(1).data());
  streams.BeginRollout();
  streams.Push(0, 0, FrameNo(9).data());
  ExpectWindowOfFrames(WindowAt(streams, 1, 0, 0), {1, 1, 1, 1, 9});
}

TEST(MotionStreams, WindowIsChannelMajorOldestFirstNewestLast) {
  MotionStreams streams(1, 3, 5);
  streams.Restart(0, FrameNo(0).data());
  streams.BeginRollout();
  for (int k = 1; k <= 3; ++k) streams.Push(0, k - 1, FrameNo(k).data());
  const torch::Tensor window = WindowAt(streams, 1, 2, 0);
  ExpectWindowOfFrames(window, {0, 0, 1, 2, 3});
  // Spelled out for two entries: channel 2 of the newest frame, channel 32 of frame 1.
  EXPECT_EQ(window[2][4].item<float>(), 302.0f);
  EXPECT_EQ(window[32][2].item<float>(), 132.0f);
}

// After k pushes of frames 1..k onto a restart with frame 0, the window ending at frame k holds
// frames max(0, k - H + 1 + t): the last H frames, padded with frame 0 while there are fewer.
TEST(MotionStreams, WindowsSlideOverManyPushesAndRollouts) {
  for (int h : {2, 3, 5, 51}) {
    constexpr int kSteps = 4;
    MotionStreams streams(1, kSteps, h);
    streams.Restart(0, FrameNo(0).data());
    int k = 0;
    for (int rollout = 0; rollout < h; ++rollout) {
      streams.BeginRollout();
      for (int step = 0; step < kSteps; ++step) streams.Push(0, step, FrameNo(++k).data());
      for (int step = 0; step < kSteps; ++step) {
        const int newest = k - kSteps + 1 + step;
        std::vector<int> frames;
        for (int t = 0; t < h; ++t) frames.push_back(std::max(0, newest - h + 1 + t));
        SCOPED_TRACE(testing::Message() << "H = " << h << ", newest frame " << newest);
        ExpectWindowOfFrames(WindowAt(streams, 1, step, 0), frames);
      }
    }
  }
}

// An episode that ends at a step still has that step's window (its final frame newest); the next
// step's window belongs to the new episode alone. Two envs keep their streams apart.
TEST(MotionStreams, RestartStartsANewEpisodeAndEnvsStayApart) {
  MotionStreams streams(2, 3, 4);
  streams.Restart(0, FrameNo(0).data());
  streams.Restart(1, FrameNo(50).data());
  streams.BeginRollout();
  streams.Push(0, 0, FrameNo(1).data());
  streams.Push(1, 0, FrameNo(51).data());
  streams.Push(0, 1, FrameNo(2).data());  // env 0's episode ends here
  streams.Restart(0, FrameNo(7).data());
  streams.Push(1, 1, FrameNo(52).data());
  streams.Push(0, 2, FrameNo(8).data());
  streams.Push(1, 2, FrameNo(53).data());
  ExpectWindowOfFrames(WindowAt(streams, 2, 1, 0), {0, 0, 1, 2});
  ExpectWindowOfFrames(WindowAt(streams, 2, 2, 0), {7, 7, 7, 8});
  ExpectWindowOfFrames(WindowAt(streams, 2, 2, 1), {50, 51, 52, 53});
  // The next rollout continues from the kept frames.
  streams.BeginRollout();
  for (int step = 0; step < 3; ++step) {
    streams.Push(0, step, FrameNo(9 + step).data());
    streams.Push(1, step, FrameNo(54 + step).data());
  }
  ExpectWindowOfFrames(WindowAt(streams, 2, 0, 0), {7, 7, 8, 9});
  ExpectWindowOfFrames(WindowAt(streams, 2, 0, 1), {51, 52, 53, 54});
}

TEST(MotionStreams, WindowOfOneIsTheNewestFrame) {
  MotionStreams streams(1, 1, 1);
  streams.Restart(0, FrameNo(0).data());
  streams.BeginRollout();
  streams.Push(0, 0, FrameNo(2).data());
  ExpectWindowOfFrames(WindowAt(streams, 1, 0, 0), {2});
}

}  // namespace
}  // namespace flsd
