#include "skills/learning/networks/discriminator.h"
#include "skills/learning/tasks/skill_discovery_task.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cmath>
#include <vector>

namespace flsd {
namespace {

torch::Tensor Skills(const std::vector<int64_t>& k) { return torch::tensor(k, torch::kLong); }

TEST(IntrinsicReward, UniformPosteriorEarnsNothing) {
  // q(k | o) = 1/8 = p(k): the observation says nothing about the skill.
  const torch::Tensor log_probs = torch::full({3, 8}, -std::log(8.0));
  const torch::Tensor r = IntrinsicReward(log_probs, Skills({0, 5, 7}));
  ASSERT_EQ(r.sizes(), torch::IntArrayRef({3}));
  EXPECT_TRUE(torch::allclose(r, torch::zeros({3}), 0.0, 1e-6)) << r;
}

TEST(IntrinsicReward, CertainPosteriorEarnsLogK) {
  // log q(k | o) = 0 for the true skill: the most the reward can be, log 8.
  torch::Tensor log_probs = torch::full({2, 8}, -1e9);
  log_probs[0][2] = 0.0;
  log_probs[1][6] = 0.0;
  const torch::Tensor r = IntrinsicReward(log_probs, Skills({2, 6}));
  EXPECT_NEAR(r[0].item<double>(), std::log(8.0), 1e-6);
  EXPECT_NEAR(r[1].item<double>(), std::log(8.0), 1e-6);
}

TEST(IntrinsicReward, ThreeSkillsByHand) {
  // q = (0.7, 0.2, 0.1), p(k) = 1/3: r = log q(k) + log 3, i.e. log 2.1, log 0.6, log 0.3.
  const torch::Tensor log_probs = torch::log(torch::tensor({0.7, 0.2, 0.1}, torch::kFloat64)).repeat({3, 1});
  const torch::Tensor r = IntrinsicReward(log_probs, Skills({0, 1, 2}));
  EXPECT_NEAR(r[0].item<double>(), std::log(2.1), 1e-12);
  EXPECT_NEAR(r[1].item<double>(), std::log(0.6), 1e-12);
  EXPECT_NEAR(r[2].item<double>(), std::log(0.3), 1e-12);
}

TEST(DiscriminatorLoss, IsTheMeanNegativeLogLikelihood) {
  const torch::Tensor log_probs =
      torch::log(torch::tensor({{0.7, 0.2, 0.1}, {0.25, 0.25, 0.5}, {0.1, 0.6, 0.3}}, torch::kFloat64));
  // -(log 0.7 + log 0.5 + log 0.6) / 3
  const double expected = -(std::log(0.7) + std::log(0.5) + std::log(0.6)) / 3.0;
  EXPECT_NEAR(DiscriminatorLoss(log_probs, Skills({0, 2, 1})).item<double>(), expected, 1e-12);
}

TEST(Discriminator, LogProbsAreNormalised) {
  torch::manual_seed(0);
  Discriminator d(5, 4, DiscriminatorConfig{});
  EXPECT_EQ(d->num_skills(), 4);
  const torch::Tensor log_probs = d->LogProbs(torch::randn({6, 5}) * 3.0);
  ASSERT_EQ(log_probs.sizes(), torch::IntArrayRef({6, 4}));
  EXPECT_TRUE(torch::allclose(log_probs.exp().sum(1), torch::ones({6}), 0.0, 1e-5));
}

// Skill k's observations around (+2, +2) or (-2, -2), spread 0.5: separable almost surely.
void TwoClusters(int64_t n, torch::Tensor& x, torch::Tensor& k) {
  k = torch::randint(0, 2, {n}, torch::kLong);
  const torch::Tensor centre = (k.to(torch::kFloat32) * 4.0 - 2.0).unsqueeze(1).expand({n, 2});
  x = centre + 0.5 * torch::randn({n, 2});
}

TEST(Discriminator, LearnsToTellTwoSeparatedSkillsApart) {
  torch::manual_seed(1);
  DiscriminatorConfig config;
  config.hidden = {16, 16};
  Discriminator d(2, 2, config);
  torch::optim::Adam optimizer(d->parameters(), torch::optim::AdamOptions(1e-2));
  torch::Tensor x, k;
  for (int step = 0; step < 150; ++step) {
    TwoClusters(128, x, k);
    const torch::Tensor loss = DiscriminatorLoss(d->LogProbs(x), k);
    optimizer.zero_grad();
    loss.backward();
    optimizer.step();
  }
  torch::NoGradGuard no_grad;
  TwoClusters(2000, x, k);
  const torch::Tensor log_probs = d->LogProbs(x);
  const double accuracy = (log_probs.argmax(1) == k).to(torch::kFloat64).mean().item<double>();
  EXPECT_GT(accuracy, 0.95);
  // And the policy's reward approaches its ceiling log 2.
  EXPECT_GT(IntrinsicReward(log_probs, k).mean().item<double>(), 0.9 * std::log(2.0));
}

TEST(Blurred, AddsEachPartsNoiseAndNothingWhenOff) {
  torch::manual_seed(3);
  const torch::Tensor x = torch::zeros({20000, 5});
  EXPECT_TRUE(torch::equal(Blurred(x, DiscriminatorConfig{}), x));
  DiscriminatorConfig config;
  config.position_noise = 1.5;
  config.feature_noise = 0.2;
  const torch::Tensor std = Blurred(x, config).std(0);
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(std[i].item<double>(), i < 2 ? 1.5 : 0.2, 0.03) << "column " << i;
}

// Two skills at q = (+d, 0) and (-d, 0), trained with 1 m of position noise: the reward (read on
// clean q) is about zero for skills 0.1 m apart and near its ceiling log 2 for skills 10 m apart.
double RewardOfSkillsApart(double d) {
  torch::manual_seed(4);
  DiscriminatorConfig config;
  config.hidden = {16, 16};
  config.position_noise = 1.0;
  Discriminator disc(2, 2, config);
  torch::optim::Adam optimizer(disc->parameters(), torch::optim::AdamOptions(1e-2));
  const auto samples = [d](torch::Tensor& x, torch::Tensor& k) {
    k = torch::randint(0, 2, {256}, torch::kLong);
    x = torch::zeros({256, 2});
    x.select(1, 0).copy_((k.to(torch::kFloat32) * 2.0 - 1.0) * d);
  };
  torch::Tensor x, k;
  for (int step = 0; step < 300; ++step) {
    samples(x, k);
    const torch::Tensor loss = DiscriminatorLoss(disc->LogProbs(Blurred(x, config)), k);
    optimizer.zero_grad();
    loss.backward();
    optimizer.step();
  }
  torch::NoGradGuard no_grad;
  samples(x, k);
  return IntrinsicReward(disc->LogProbs(x), k).mean().item<double>();
}

TEST(Discriminator, PositionNoiseRewardsDistanceNotCreeping) {
  EXPECT_LT(RewardOfSkillsApart(0.1), 0.1);
  EXPECT_GT(RewardOfSkillsApart(10.0), 0.6);  // log 2 = 0.69
}

}  // namespace
}  // namespace flsd
