#include "skills/learning/algorithms/symmetry.h"

#include <vector>

#include "core/check.h"

namespace flsd {

torch::Tensor MirrorAlong(const mirror::SignedPermutation& p, const torch::Tensor& x, int64_t dim) {
  const int64_t d = dim < 0 ? dim + x.dim() : dim;
  FLSD_DEMAND(x.size(d) == p.size());
  const std::vector<int64_t> source(p.source.begin(), p.source.end());
  const torch::Tensor index = torch::tensor(source, torch::kLong);
  std::vector<int64_t> shape(x.dim() - d, 1);
  shape[0] = p.size();
  const torch::Tensor sign = torch::tensor(p.sign, torch::kFloat32).view(shape).to(x.scalar_type());
  return x.index_select(d, index) * sign;
}

mirror::SkillPairing SkillPairingOf(int num_skills, const SymmetryConfig& config) {
  return mirror::SkillPairing(num_skills, config.enabled ? config.self_paired_skills : num_skills);
}

torch::Tensor PairIndex(const mirror::SkillPairing& pairing) {
  std::vector<int64_t> pairs;
  for (int k = 0; k < pairing.num_skills(); ++k) pairs.push_back(pairing(k));
  return torch::tensor(pairs, torch::kLong);
}

}  // namespace flsd
