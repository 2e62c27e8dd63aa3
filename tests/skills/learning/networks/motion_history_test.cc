#include "skills/learning/networks/motion_history.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
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

std::vector<float> Window(const MotionHistory& history, int window, const Frame& newest) {
  std::vector<float> out(kMotionObsSize * window, NAN);  // an unwritten entry fails every check
  history.WriteWindow(newest.data(), out.data());
  return out;
}

// Checks that time step t of the [33, H] window holds frame frames[t].
void ExpectWindowOfFrames(const std::vector<float>& out, const std::vector<int>& frames) {
  const int h = static_cast<int>(frames.size());
  ASSERT_EQ(out.size(), static_cast<size_t>(kMotionObsSize * h));
  for (int t = 0; t < h; ++t) {
    for (int c = 0; c < kMotionObsSize; ++c) {
      ASSERT_EQ(out[c * h + t], FrameNo(frames[t])[c]) << "channel " << c << ", time " << t;
    }
  }
}

TEST(MotionHistory, RestartReplicatesTheFirstFrame) {
  MotionHistory history(5);
  history.Restart(FrameNo(1).data());
  ExpectWindowOfFrames(Window(history, 5, FrameNo(9)), {1, 1, 1, 1, 9});
}

TEST(MotionHistory, WindowIsChannelMajorOldestFirstNewestLast) {
  MotionHistory history(5);
  history.Restart(FrameNo(0).data());
  history.Push(FrameNo(1).data());
  history.Push(FrameNo(2).data());
  const std::vector<float> out = Window(history, 5, FrameNo(3));
  ExpectWindowOfFrames(out, {0, 0, 1, 2, 3});
  // Spelled out for two entries: channel 2 of the newest frame, channel 32 of frame 1.
  EXPECT_EQ(out[2 * 5 + 4], 302.0f);
  EXPECT_EQ(out[32 * 5 + 2], 132.0f);
}

// After k pushes of frames 1..k onto a restart with frame 0, time step t < H - 1 holds frame
// max(0, k - (H - 1) + 1 + t): the last H - 1 frames, padded with frame 0 while there are fewer.
TEST(MotionHistory, RingWrapsAroundOverManyPushes) {
  for (int h : {2, 3, 5, 51}) {
    MotionHistory history(h);
    history.Restart(FrameNo(0).data());
    for (int k = 0; k <= 3 * h + 2; ++k) {
      if (k > 0) history.Push(FrameNo(k).data());
      std::vector<int> frames;
      for (int t = 0; t < h - 1; ++t) frames.push_back(std::max(0, k - (h - 1) + 1 + t));
      frames.push_back(1000);  // the newest, passed to WriteWindow
      SCOPED_TRACE(testing::Message() << "H = " << h << ", pushes = " << k);
      ExpectWindowOfFrames(Window(history, h, FrameNo(1000)), frames);
    }
  }
}

TEST(MotionHistory, RestartDropsThePreviousEpisode) {
  MotionHistory history(4);
  history.Restart(FrameNo(0).data());
  for (int k = 1; k <= 5; ++k) history.Push(FrameNo(k).data());
  history.Restart(FrameNo(7).data());
  ExpectWindowOfFrames(Window(history, 4, FrameNo(8)), {7, 7, 7, 8});
  history.Push(FrameNo(8).data());
  ExpectWindowOfFrames(Window(history, 4, FrameNo(9)), {7, 7, 8, 9});
}

TEST(MotionHistory, WindowOfOneIsTheNewestFrame) {
  MotionHistory history(1);
  history.Restart(FrameNo(0).data());
  history.Push(FrameNo(1).data());
  ExpectWindowOfFrames(Window(history, 1, FrameNo(2)), {2});
}

}  // namespace
}  // namespace flsd
