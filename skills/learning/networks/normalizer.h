#pragma once
#include <torch/torch.h>

#include "skills/learning/runners/communicator.h"

namespace flsd {

// Running mean and variance of observations, for normalising network inputs. Statistics are kept
// in double precision and merged exactly (Chan et al.'s parallel update), so batches can be added
// in any grouping, and statistics from several workers combined, with the same result.
class RunningNormalizerImpl : public torch::nn::Module {
 public:
  explicit RunningNormalizerImpl(int size);

  // Adds a batch [B, size] of observations to the statistics.
  void Update(const torch::Tensor& batch);
  // Merges statistics gathered elsewhere (count, mean [size], population variance [size]).
  void Merge(double count, const torch::Tensor& mean, const torch::Tensor& variance);
  // (x - mean) / Std(), as float.
  torch::Tensor Normalize(const torch::Tensor& x) const;
  // sqrt(variance) + kEps: what Normalize divides by (exported with skill libraries). As in
  // rsl_rl's EmpiricalNormalization, eps is added to the std, not the variance, so that a nearly
  // constant input (gravity z while standing) is not blown up by a tiny std.
  torch::Tensor Std() const { return torch::sqrt(variance_) + kEps; }

  static constexpr double kEps = 1e-2;

  int size() const { return static_cast<int>(mean_.size(0)); }
  double count() const { return count_.item<double>(); }
  const torch::Tensor& mean() const { return mean_; }
  const torch::Tensor& variance() const { return variance_; }

 private:
  torch::Tensor mean_, variance_, count_;  // float64 buffers, saved with checkpoints
};
TORCH_MODULE(RunningNormalizer);

// Adds every rank's batch [B, size] to the statistics of every rank, merged in rank order: what
// one process adding the whole batch would get (the merge is exact for any grouping).
void UpdateNormalizer(RunningNormalizer& normalizer, const torch::Tensor& batch, const Communicator& comm);

// Normalises the first normalizer->size() columns of x [B, >= size] and passes the rest through:
// the policy's o^m and previous action are normalised, its one-hot skill is not.
torch::Tensor NormalizeLeadingColumns(const RunningNormalizer& normalizer, const torch::Tensor& x);

}  // namespace flsd
