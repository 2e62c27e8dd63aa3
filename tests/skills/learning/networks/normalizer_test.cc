#include "skills/learning/networks/normalizer.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cmath>
#include <vector>

namespace flsd {
namespace {

// 100 observations of 3 columns with very different offsets and scales.
torch::Tensor Data() {
  torch::manual_seed(3);
  return torch::randn({100, 3}, torch::kFloat64) * torch::tensor({1.0, 10.0, 0.01}, torch::kFloat64) +
         torch::tensor({5.0, -3.0, 100.0}, torch::kFloat64);
}

// A normalizer fed `data` in consecutive batches of the given sizes.
RunningNormalizer FedInBatches(const torch::Tensor& data, const std::vector<int64_t>& sizes) {
  RunningNormalizer n(static_cast<int>(data.size(1)));
  int64_t begin = 0;
  for (int64_t size : sizes) {
    n->Update(data.slice(0, begin, begin + size));
    begin += size;
  }
  EXPECT_EQ(begin, data.size(0));
  return n;
}

void ExpectStatsOf(const RunningNormalizer& n, const torch::Tensor& data) {
  EXPECT_EQ(n->count(), static_cast<double>(data.size(0)));
  EXPECT_TRUE(torch::allclose(n->mean(), data.mean(0), 0.0, 1e-10)) << n->mean() << data.mean(0);
  // Population variance (divided by n, not n - 1).
  EXPECT_TRUE(torch::allclose(n->variance(), data.var(0, /*unbiased=*/false), 0.0, 1e-10))
      << n->variance() << data.var(0, false);
}

// Before any data: mean 0 and variance 1, so it divides by 1 + eps only.
TEST(RunningNormalizer, StartsNearTheIdentity) {
  RunningNormalizer n(3);
  EXPECT_EQ(n->size(), 3);
  EXPECT_EQ(n->count(), 0.0);
  const torch::Tensor x = torch::tensor({{1.5f, -2.0f, 0.25f}});
  EXPECT_TRUE(torch::allclose(n->Normalize(x), x / (1.0 + RunningNormalizerImpl::kEps), 1e-7, 0.0));
}

TEST(RunningNormalizer, AnyBatchingGivesTheStatisticsOfTheWhole) {
  const torch::Tensor data = Data();
  std::vector<int64_t> ones(100, 1);
  for (const std::vector<int64_t>& sizes :
       std::vector<std::vector<int64_t>>{{100}, {30, 70}, {7, 13, 80}, {0, 50, 0, 50}, ones}) {
    SCOPED_TRACE(testing::Message() << sizes.size() << " batches");
    ExpectStatsOf(FedInBatches(data, sizes), data);
  }
}

TEST(RunningNormalizer, FloatBatchesAreAccumulatedInDouble) {
  const torch::Tensor data = Data().to(torch::kFloat32);
  const RunningNormalizer n = FedInBatches(data, {60, 40});
  EXPECT_EQ(n->mean().scalar_type(), torch::kFloat64);
  ExpectStatsOf(n, data.to(torch::kFloat64));
}

TEST(RunningNormalizer, MergingTwoWorkersStatisticsGivesTheUnion) {
  const torch::Tensor data = Data();
  RunningNormalizer a = FedInBatches(data.slice(0, 0, 40), {40});
  const RunningNormalizer b = FedInBatches(data.slice(0, 40, 100), {25, 35});
  a->Merge(b->count(), b->mean(), b->variance());
  ExpectStatsOf(a, data);
  // Merging nothing changes nothing; merging into an empty one copies.
  a->Merge(0.0, torch::zeros({3}, torch::kFloat64), torch::ones({3}, torch::kFloat64));
  ExpectStatsOf(a, data);
  RunningNormalizer empty(3);
  empty->Merge(a->count(), a->mean(), a->variance());
  ExpectStatsOf(empty, data);
}

TEST(RunningNormalizer, NormalizedDataHasZeroMeanAndUnitVariance) {
  const torch::Tensor data = Data();
  const RunningNormalizer n = FedInBatches(data, {100});
  const torch::Tensor y = n->Normalize(data);
  EXPECT_EQ(y.scalar_type(), torch::kFloat32);
  EXPECT_TRUE(torch::allclose(y.mean(0).to(torch::kFloat64), torch::zeros({3}, torch::kFloat64), 0.0, 1e-5));
  // var / (sqrt(var) + eps)^2: the eps shows in the third column, whose variance is about 1e-4.
  const torch::Tensor var = data.var(0, false);
  const torch::Tensor expected = var / (var.sqrt() + RunningNormalizerImpl::kEps).pow(2);
  EXPECT_TRUE(torch::allclose(y.to(torch::kFloat64).var(0, false), expected, 0.0, 1e-5));
}

TEST(RunningNormalizer, StdIsSqrtOfVarianceThenPlusEps) {
  RunningNormalizer n(2);
  // Column 0 constant (variance 0), column 1 alternating +-2 about 1 (variance 4).
  n->Update(torch::tensor({{7.0, -1.0}, {7.0, 3.0}, {7.0, -1.0}, {7.0, 3.0}}, torch::kFloat64));
  const torch::Tensor std = n->Std();
  EXPECT_EQ(std.scalar_type(), torch::kFloat64);
  EXPECT_DOUBLE_EQ(std[0].item<double>(), RunningNormalizerImpl::kEps);  // 0.01
  EXPECT_DOUBLE_EQ(std[1].item<double>(), 2.0 + RunningNormalizerImpl::kEps);
  // A constant column maps to 0, not to a division by zero.
  const torch::Tensor y = n->Normalize(torch::tensor({{7.0f, 5.0f}}));
  EXPECT_EQ(y[0][0].item<float>(), 0.0f);
  EXPECT_NEAR(y[0][1].item<float>(), 4.0 / (2.0 + RunningNormalizerImpl::kEps), 1e-6);
}

TEST(RunningNormalizer, StatisticsAreCheckpointedBuffers) {
  RunningNormalizer n(3);
  std::vector<std::string> names;
  for (const auto& item : n->named_buffers()) names.push_back(item.key());
  EXPECT_EQ(names, (std::vector<std::string>{"mean", "variance", "count"}));
  EXPECT_TRUE(n->parameters().empty()) << "the statistics must not be trained";
}

// The one-hot skill columns after the normalised ones must pass through untouched.
TEST(NormalizeLeadingColumns, NormalizesOnlyTheFirstSizeColumns) {
  const RunningNormalizer n = FedInBatches(Data(), {100});
  const torch::Tensor x =
      torch::cat({Data().slice(0, 0, 5).to(torch::kFloat32), torch::eye(5).slice(1, 0, 2)}, 1);
  const torch::Tensor y = NormalizeLeadingColumns(n, x);
  ASSERT_EQ(y.sizes(), x.sizes());
  EXPECT_TRUE(torch::equal(y.slice(1, 0, 3), n->Normalize(x.slice(1, 0, 3))));
  EXPECT_TRUE(torch::equal(y.slice(1, 3), x.slice(1, 3)));
}

}  // namespace
}  // namespace flsd
