// The tensor form of the mirror maps: MirrorAlong agrees with robot/mirror.h's per-sample maps
// along any dimension, and the skills' pair index is the pairing.

#include "skills/learning/algorithms/symmetry.h"

#include <gtest/gtest.h>

#include <vector>

namespace flsd {
namespace {

TEST(Symmetry, MirrorAlongAgreesWithThePerSampleMapOnEveryFrameOfAWindow) {
  torch::manual_seed(2);
  const torch::Tensor windows = torch::randn({3, kMotionObsSize, 7});  // [B, 33, H]
  const mirror::SignedPermutation motion = mirror::MotionObservation();
  const torch::Tensor mirrored = MirrorAlong(motion, windows, 1).contiguous();
  for (int b = 0; b < 3; ++b) {
    for (int h = 0; h < 7; ++h) {
      const torch::Tensor frame = windows[b].select(1, h).contiguous();
      std::vector<float> expected(kMotionObsSize);
      motion.Apply(frame.data_ptr<float>(), expected.data());
      for (int i = 0; i < kMotionObsSize; ++i) EXPECT_EQ(mirrored[b][i][h].item<float>(), expected[i]);
    }
  }
  const torch::Tensor positions = torch::tensor({{1.0f, 2.0f}, {-3.0f, -4.0f}});
  EXPECT_TRUE(torch::equal(MirrorAlong(mirror::PlanarPosition(), positions, 1),
                           torch::tensor({{1.0f, -2.0f}, {-3.0f, 4.0f}})));
}

TEST(Symmetry, PairsFollowTheConfig) {
  SymmetryConfig config;
  config.enabled = true;
  config.self_paired_skills = 2;
  EXPECT_TRUE(torch::equal(PairIndex(SkillPairingOf(6, config)), torch::tensor({2, 3, 0, 1, 4, 5}, torch::kLong)));
  config.enabled = false;  // every skill its own image
  EXPECT_TRUE(torch::equal(PairIndex(SkillPairingOf(3, config)), torch::tensor({0, 1, 2}, torch::kLong)));
}

}  // namespace
}  // namespace flsd
