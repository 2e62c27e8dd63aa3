#include "skills/learning/networks/normalizer.h"

#include "core/check.h"

namespace flsd {
RunningNormalizerImpl::RunningNormalizerImpl(int size) {
  mean_ = register_buffer("mean", torch::zeros({size}, torch::kFloat64));
  variance_ = register_buffer("variance", torch::ones({size}, torch::kFloat64));
  count_ = register_buffer("count", torch::zeros({}, torch::kFloat64));
}

void RunningNormalizerImpl::Update(const torch::Tensor& batch) {
  FLSD_DEMAND(batch.dim() == 2 && batch.size(1) == mean_.size(0));
  if (batch.size(0) == 0) return;
  const torch::Tensor x = batch.to(torch::kFloat64);
  Merge(static_cast<double>(x.size(0)), x.mean(0), x.var(0, /*unbiased=*/false));
}

void RunningNormalizerImpl::Merge(double count, const torch::Tensor& mean, const torch::Tensor& variance) {
  torch::NoGradGuard no_grad;
  const double n_a = count_.item<double>();
  const double n = n_a + count;
  if (count <= 0.0) return;
  const torch::Tensor delta = mean.to(torch::kFloat64) - mean_;
  // Population variance of the union: within-group sums of squares plus the between-group term.
  const torch::Tensor m2 = variance_ * n_a + variance.to(torch::kFloat64) * count +
                           delta.pow(2) * (n_a * count / n);
  mean_.add_(delta * (count / n));
  variance_.copy_(m2 / n);
  count_.fill_(n);
}

torch::Tensor RunningNormalizerImpl::Normalize(const torch::Tensor& x) const {
  return ((x.to(torch::kFloat64) - mean_) / Std()).to(torch::kFloat32);
}

void UpdateNormalizer(RunningNormalizer& normalizer, const torch::Tensor& batch, const Communicator& comm) {
  if (comm.size() == 1) {
    normalizer->Update(batch);
    return;
  }
  const torch::Tensor x = batch.to(torch::kFloat64);
  const int64_t size = x.size(1);
  // Each rank's count, mean and population variance, side by side.
  std::vector<double> local(1 + 2 * size);
  local[0] = static_cast<double>(x.size(0));
  const torch::Tensor mean = x.mean(0).contiguous(), variance = x.var(0, /*unbiased=*/false).contiguous();
  std::copy(mean.data_ptr<double>(), mean.data_ptr<double>() + size, local.begin() + 1);
  std::copy(variance.data_ptr<double>(), variance.data_ptr<double>() + size, local.begin() + 1 + size);
  std::vector<double> all = comm.Gather(local);
  const auto float64 = torch::TensorOptions().dtype(torch::kFloat64);
  for (int r = 0; r < comm.size(); ++r) {
    double* stats = all.data() + r * local.size();
    normalizer->Merge(stats[0], torch::from_blob(stats + 1, {size}, float64),
                      torch::from_blob(stats + 1 + size, {size}, float64));
  }
}

torch::Tensor NormalizeLeadingColumns(const RunningNormalizer& normalizer, const torch::Tensor& x) {
  const int64_t n = normalizer->size();
  return torch::cat({normalizer->Normalize(x.slice(1, 0, n)), x.slice(1, n)}, 1);
}

}  // namespace flsd
