#pragma once
// Left-right symmetry augmentation of skill discovery (Mittal et al., ICRA 2024, as rsl_rl and
// ETH's D3 do it): every rollout also trains PPO, the discriminator and the PAE on its mirror
// image (robot/mirror.h), with skill k's mirror image labelled as its pair's. Skill k and its pair
// then learn mirror-image motions, and the library gets both turning directions of every mover.

#include <torch/torch.h>

#include "core/config.h"
#include "robot/mirror.h"

namespace flsd {

struct SymmetryConfig {
  bool enabled = false;
  // Skills that are their own mirror image (robot/mirror.h, SkillPairing); the rest form pairs.
  int self_paired_skills = 4;
  template <class V>
  void Visit(V& v) {
    v("enabled", enabled);
    v("self_paired_skills", self_paired_skills, Bounds<int>{0, 10000});
  }
};

// The skills' pairing under `config`; without symmetry every skill is its own pair.
mirror::SkillPairing SkillPairingOf(int num_skills, const SymmetryConfig& config);

// x's mirror image by `p` along dimension `dim` (whose size must be p.size()).
torch::Tensor MirrorAlong(const mirror::SignedPermutation& p, const torch::Tensor& x, int64_t dim);

// The skills' mirror images as an index tensor [N_k] (int64): pairs[k] = pairing(k).
torch::Tensor PairIndex(const mirror::SkillPairing& pairing);

}  // namespace flsd
