#pragma once
#include <torch/torch.h>

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
  // (x - mean) / sqrt(variance + eps), as float.
  torch::Tensor Normalize(const torch::Tensor& x) const;

  int size() const { return static_cast<int>(mean_.size(0)); }
  double count() const { return count_.item<double>(); }
  const torch::Tensor& mean() const { return mean_; }
  const torch::Tensor& variance() const { return variance_; }

 private:
  torch::Tensor mean_, variance_, count_;  // float64 buffers, saved with checkpoints
};
TORCH_MODULE(RunningNormalizer);

}  // namespace flsd
