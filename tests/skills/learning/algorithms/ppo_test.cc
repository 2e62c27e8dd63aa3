#include "skills/learning/algorithms/ppo.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cmath>
#include <vector>

#include "core/check.h"
#include "skills/learning/networks/actor_critic.h"

namespace flsd {
namespace {

constexpr double kGamma = 0.9, kLambda = 0.8;

// Three steps of two envs, [T, N]. Env 0: rewards 1, 2, 3, values 0.5, 1, 1.5, its episode ends
// after step 1. Env 1: no reward, zero values, never ends.
Rollout HandRollout() {
  Rollout r;
  r.rewards = torch::tensor({{1.0f, 0.0f}, {2.0f, 0.0f}, {3.0f, 0.0f}});
  r.values = torch::tensor({{0.5f, 0.0f}, {1.0f, 0.0f}, {1.5f, 0.0f}});
  r.dones = torch::tensor({{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 0.0f}});
  r.timeouts = torch::zeros({3, 2});
  return r;
}
// V of the states after the last step.
torch::Tensor LastValues() { return torch::tensor({2.0f, 1.0f}); }

void ExpectColumn(const torch::Tensor& x, int env, const std::vector<double>& expected) {
  for (size_t t = 0; t < expected.size(); ++t) {
    EXPECT_NEAR(x[t][env].item<double>(), expected[t], 1e-5) << "t = " << t << ", env " << env;
  }
}

// GAE backwards: delta_t = r_t + g V_{t+1} (1 - d_t) - V_t, A_t = delta_t + g l (1 - d_t) A_{t+1},
// return_t = A_t + V_t.
TEST(ComputeReturns, GaeByHand) {
  const Returns out = ComputeReturns(HandRollout(), LastValues(), kGamma, kLambda);
  // Env 0. t = 2: 3 + 0.9 * 2 - 1.5 = 3.3, return 4.8.
  //        t = 1 (done): 2 - 1 = 1, no bootstrap, no carried advantage; return 2.
  //        t = 0: 1 + 0.9 * 1 - 0.5 = 1.4, A = 1.4 + 0.72 * 1 = 2.12, return 2.62.
  ExpectColumn(out.returns, 0, {2.62, 2.0, 4.8});
  // Env 1. t = 2: 0.9 * 1 = 0.9; t = 1: 0 + 0.72 * 0.9 = 0.648; t = 0: 0.72 * 0.648 = 0.46656.
  ExpectColumn(out.returns, 1, {0.46656, 0.648, 0.9});
}

// A time-out is not a real end: gamma V(s_1) is added to r_1 (as rsl_rl does), but the GAE
// recursion is still cut there.
TEST(ComputeReturns, TimeOutBootstrapsFromTheValue) {
  Rollout r = HandRollout();
  r.timeouts[1][0] = 1.0f;
  const Returns out = ComputeReturns(r, LastValues(), kGamma, kLambda);
  // t = 1: r = 2 + 0.9 * 1 = 2.9, delta = 1.9, return 2.9.
  // t = 0: A = 1.4 + 0.72 * 1.9 = 2.768, return 3.268. t = 2 is unchanged.
  ExpectColumn(out.returns, 0, {3.268, 2.9, 4.8});
  ExpectColumn(out.returns, 1, {0.46656, 0.648, 0.9});
}

TEST(ComputeReturns, AdvantagesAreNormalisedOverTheBatch) {
  const Rollout r = HandRollout();
  const Returns out = ComputeReturns(r, LastValues(), kGamma, kLambda);
  ASSERT_EQ(out.advantages.sizes(), r.rewards.sizes());
  EXPECT_NEAR(out.advantages.mean().item<double>(), 0.0, 1e-6);
  EXPECT_NEAR(out.advantages.std().item<double>(), 1.0, 1e-5);  // unbiased, as rsl_rl
  // The raw advantages are return - value; normalising keeps their order and spacing.
  const torch::Tensor raw = out.returns - r.values;
  EXPECT_TRUE(torch::allclose(out.advantages, (raw - raw.mean()) / raw.std(), 1e-5, 1e-5));
}

// With reward streams ([T, N, S]) each stream's returns are its own GAE, and the advantages are
// each stream's normalised advantages, summed: a stream 1000 times larger weighs no more.
TEST(ComputeReturns, StreamsAreNormalisedEachOnItsOwnThenSummed) {
  const Rollout first = HandRollout();
  Rollout second = HandRollout();
  second.rewards = -1000.0f * second.rewards.flip(0);
  second.values = 10.0f * second.values;
  const torch::Tensor second_last = torch::tensor({-50.0f, 3.0f});
  Rollout both = HandRollout();
  both.rewards = torch::stack({first.rewards, second.rewards}, 2);
  both.values = torch::stack({first.values, second.values}, 2);
  const Returns out = ComputeReturns(both, torch::stack({LastValues(), second_last}, 1), kGamma, kLambda);
  const Returns one = ComputeReturns(first, LastValues(), kGamma, kLambda);
  const Returns two = ComputeReturns(second, second_last, kGamma, kLambda);
  ASSERT_EQ(out.returns.sizes(), both.rewards.sizes());
  EXPECT_TRUE(torch::allclose(out.returns.select(2, 0), one.returns, 1e-5, 1e-5));
  EXPECT_TRUE(torch::allclose(out.returns.select(2, 1), two.returns, 1e-3, 1e-5));
  ASSERT_EQ(out.advantages.sizes(), first.rewards.sizes());
  EXPECT_TRUE(torch::allclose(out.advantages, one.advantages + two.advantages, 1e-5, 1e-5));
}

ActorCritic TinyPolicy(int obs, int actions) {
  PolicyConfig config;
  config.actor_hidden = {16};
  config.critic_hidden = {16};
  config.init_std = 1.0;
  return ActorCritic(obs, obs, actions, config);
}

void SetLogStd(ActorCritic& policy, const std::vector<float>& log_std) {
  torch::NoGradGuard no_grad;
  policy->named_parameters()["log_std"].copy_(torch::tensor(log_std));
}

TEST(ActorCritic, LogProbIsTheDiagonalGaussianDensity) {
  torch::manual_seed(0);
  ActorCritic policy = TinyPolicy(3, 2);
  SetLogStd(policy, {std::log(0.5f), std::log(2.0f)});
  EXPECT_TRUE(torch::allclose(policy->Std(), torch::tensor({0.5f, 2.0f})));
  const torch::Tensor mean = torch::tensor({{0.0f, 1.0f}, {-1.0f, 3.0f}});
  const torch::Tensor actions = torch::tensor({{0.5f, -1.0f}, {-1.0f, 3.0f}});
  const torch::Tensor distribution = torch::cat({mean, policy->Std().expand_as(mean)}, -1);
  const torch::Tensor log_prob = policy->LogProb(distribution, actions);
  ASSERT_EQ(log_prob.sizes(), torch::IntArrayRef({2}));
  const double sigma[2] = {0.5, 2.0};
  for (int b = 0; b < 2; ++b) {
    double expected = 0.0;
    for (int j = 0; j < 2; ++j) {
      const double z = (actions[b][j].item<double>() - mean[b][j].item<double>()) / sigma[j];
      expected += -0.5 * z * z - std::log(sigma[j]) - 0.5 * std::log(2.0 * M_PI);
    }
    EXPECT_NEAR(log_prob[b].item<double>(), expected, 1e-5) << "sample " << b;
  }
}

TEST(ActorCritic, EntropyOfTheDiagonalGaussian) {
  ActorCritic policy = TinyPolicy(3, 3);
  SetLogStd(policy, {-1.0f, 0.0f, 0.7f});
  const double per_dim = 0.5 * (1.0 + std::log(2.0 * M_PI));
  const torch::Tensor entropy = policy->Entropy(policy->Distribution(torch::randn({2, 3})));
  ASSERT_EQ(entropy.sizes(), torch::IntArrayRef({2}));
  EXPECT_NEAR(entropy[1].item<double>(), -1.0 + 0.0 + 0.7 + 3 * per_dim, 1e-5);
}

// KL(N(0, 1) || N(1, 2)) = log 2 + (1 + 1) / 8 - 1/2, per dimension.
TEST(ActorCritic, KlOfGaussiansHasTheClosedForm) {
  ActorCritic policy = TinyPolicy(3, 1);
  const torch::Tensor old_distribution = torch::tensor({{0.0f, 1.0f}});
  const torch::Tensor distribution = torch::tensor({{1.0f, 2.0f}});
  EXPECT_NEAR(policy->Kl(old_distribution, distribution).item<double>(), std::log(2.0) + 2.0 / 8.0 - 0.5, 1e-6);
  EXPECT_NEAR(policy->Kl(distribution, distribution).item<double>(), 0.0, 1e-7);
}

TEST(CategoricalActorCritic, LogProbEntropyAndKlOfKnownDistributions) {
  PolicyConfig config;
  config.actor_hidden = {8};
  config.critic_hidden = {8};
  CategoricalActorCritic policy(3, 3, 4, config);
  // Logits log(0.1, 0.2, 0.3, 0.4) and the uniform distribution.
  const torch::Tensor p = torch::tensor({{0.1f, 0.2f, 0.3f, 0.4f}}).log();
  const torch::Tensor uniform = torch::zeros({1, 4});
  EXPECT_NEAR(policy->LogProb(p, torch::tensor({{2.0f}})).item<double>(), std::log(0.3), 1e-6);
  EXPECT_NEAR(policy->Entropy(uniform).item<double>(), std::log(4.0), 1e-6);
  const double entropy = -(0.1 * std::log(0.1) + 0.2 * std::log(0.2) + 0.3 * std::log(0.3) + 0.4 * std::log(0.4));
  EXPECT_NEAR(policy->Entropy(p).item<double>(), entropy, 1e-6);
  // KL(p || uniform) = log 4 - H(p).
  EXPECT_NEAR(policy->Kl(p, uniform).item<double>(), std::log(4.0) - entropy, 1e-6);
  // Samples are valid indices, as a float column.
  const torch::Tensor sample = policy->Sample(torch::zeros({100, 4}));
  EXPECT_EQ(sample.sizes(), torch::IntArrayRef({100, 1}));
  EXPECT_GE(sample.min().item<float>(), 0.0f);
  EXPECT_LE(sample.max().item<float>(), 3.0f);
}

TEST(ActorCritic, ShapesOfMeanAndValue) {
  ActorCritic policy = TinyPolicy(4, 2);
  const torch::Tensor obs = torch::randn({5, 4});
  EXPECT_EQ(policy->ActionMean(obs).sizes(), torch::IntArrayRef({5, 2}));
  EXPECT_EQ(policy->Value(obs).sizes(), torch::IntArrayRef({5}));
  EXPECT_TRUE(torch::allclose(policy->Std(), torch::ones({2})));  // init_std 1
}

// A one-step bandit: reward 1 when the first action component is positive. Each env's episode
// ends after every step.
// `reward` maps the actions [T, N, A] to rewards [T, N].
template <class Reward>
Rollout BanditRollout(PpoPolicyImpl& policy, const torch::Tensor& obs, Reward reward) {
  torch::NoGradGuard no_grad;
  Rollout r;
  const int64_t t = obs.size(0), n = obs.size(1);
  r.obs = obs;
  r.critic_obs = obs;
  r.distributions = policy.Distribution(obs);
  r.actions = policy.Sample(r.distributions);
  r.log_probs = policy.LogProb(r.distributions, r.actions);
  r.values = policy.Value(obs);
  r.rewards = reward(r.actions);
  r.dones = torch::ones({t, n});
  r.timeouts = torch::zeros({t, n});
  return r;
}

torch::Tensor FirstActionPositive(const torch::Tensor& actions) {
  return (actions.select(2, 0) > 0).to(torch::kFloat32);
}

TEST(Ppo, LearnsTheBandit) {
  torch::manual_seed(4);
  ActorCritic policy = TinyPolicy(4, 2);
  Ppo ppo(policy.ptr(), PpoConfig{});
  const torch::Tensor obs = torch::randn({8, 32, 4});  // [T, N, obs]
  auto mean_action0 = [&] {
    torch::NoGradGuard no_grad;
    return policy->ActionMean(obs).select(2, 0).mean().item<double>();
  };
  const double before = mean_action0();
  double first_reward = 0.0, last_reward = 0.0;
  for (int update = 0; update < 20; ++update) {
    const Rollout r = BanditRollout(*policy, obs, FirstActionPositive);
    const double reward = r.rewards.mean().item<double>();
    if (update == 0) first_reward = reward;
    last_reward = reward;
    const PpoStats stats = ppo.Update(r, ComputeReturns(r, torch::zeros({32}), 0.99, 0.95));
    ASSERT_TRUE(stats.finite) << "update " << update;
    EXPECT_TRUE(std::isfinite(stats.surrogate_loss) && std::isfinite(stats.value_loss) &&
                std::isfinite(stats.entropy) && std::isfinite(stats.kl));
    EXPECT_GE(stats.kl, 0.0);
    EXPECT_GE(stats.learning_rate, 1e-5);
    EXPECT_LE(stats.learning_rate, 1e-2);
    EXPECT_EQ(stats.learning_rate, ppo.learning_rate());
  }
  const double after = mean_action0();
  // Over seeds 0-11 the mean rises by 1.9 to 2.4 and the reward from about 0.5 to 1.
  EXPECT_GT(after - before, 1.0) << "mean of action 0 went from " << before << " to " << after;
  EXPECT_LT(first_reward, 0.7);
  EXPECT_GT(last_reward, 0.9);
}

// The categorical policy learns which of 5 choices pays: from 1/5 of the time to nearly always.
TEST(Ppo, CategoricalPolicyLearnsTheBandit) {
  torch::manual_seed(6);
  PolicyConfig config;
  config.actor_hidden = {16};
  config.critic_hidden = {16};
  CategoricalActorCritic policy(4, 4, 5, config);
  Ppo ppo(policy.ptr(), PpoConfig{});
  const torch::Tensor obs = torch::randn({8, 32, 4});
  auto choice3 = [](const torch::Tensor& actions) { return (actions.select(2, 0) == 3).to(torch::kFloat32); };
  double first_reward = 0.0, last_reward = 0.0;
  for (int update = 0; update < 30; ++update) {
    const Rollout r = BanditRollout(*policy, obs, choice3);
    (update == 0 ? first_reward : last_reward) = r.rewards.mean().item<double>();
    ASSERT_TRUE(ppo.Update(r, ComputeReturns(r, torch::zeros({32}), 0.99, 0.95)).finite);
  }
  EXPECT_LT(first_reward, 0.35);
  EXPECT_GT(last_reward, 0.9);
}

// legged_gym's selector problem in miniature: choice 3 earns 1 and every step costs 2 whatever
// the choice. Clipped at zero each step, every reward is 0 and nothing is learned; as two
// streams (the earning, and the cost) with their own value heads, choice 3 is learned.
TEST(Ppo, RewardStreamsLearnWhatAPerStepClipAtZeroErases) {
  PolicyConfig config;
  config.actor_hidden = {16};
  config.critic_hidden = {16};
  const torch::Tensor obs = torch::randn({8, 32, 4});
  auto choice3 = [](const torch::Tensor& actions) { return (actions.select(2, 0) == 3).to(torch::kFloat32); };
  auto share_of_choice3 = [&](CategoricalActorCritic& policy) {
    torch::NoGradGuard no_grad;
    return torch::softmax(policy->Distribution(obs), -1).select(2, 3).mean().item<double>();
  };
  for (const bool streams : {false, true}) {
    torch::manual_seed(6);
    CategoricalActorCritic policy(4, 4, 5, config, streams ? 2 : 1);
    Ppo ppo(policy.ptr(), PpoConfig{});
    for (int update = 0; update < 30; ++update) {
      Rollout r = BanditRollout(*policy, obs, choice3);
      const torch::Tensor earned = r.rewards, cost = torch::full_like(earned, -2.0f);
      {
        torch::NoGradGuard no_grad;
        r.values = policy->Value(obs);
      }
      r.rewards = streams ? torch::stack({earned, cost}, 2) : torch::clamp_min(earned + cost, 0.0f);
      const torch::Tensor last = streams ? torch::zeros({32, 2}) : torch::zeros({32});
      ASSERT_TRUE(ppo.Update(r, ComputeReturns(r, last, 0.99, 0.95)).finite);
    }
    if (streams) {
      EXPECT_GT(share_of_choice3(policy), 0.9);
    } else {
      EXPECT_LT(share_of_choice3(policy), 0.35);  // where it started, about 1/5
    }
  }
}

// KL(policy || prior) where the prior is the observation's trailing columns: (3/4, 1/4) against
// the uniform prior is 3/4 log(3/2) + 1/4 log(1/2); a choice both mask adds nothing.
TEST(CategoricalActorCritic, PriorKlOfKnownDistributions) {
  PolicyConfig config;
  config.actor_hidden = {8};
  config.critic_hidden = {8};
  CategoricalActorCritic policy(4, 4, 2, config, 1, /*prior_logits=*/true);
  EXPECT_TRUE(policy->HasPrior());
  const torch::Tensor obs = torch::tensor({{0.5f, -1.0f, 0.0f, 0.0f}, {0.5f, -1.0f, 0.0f, -1e4f}});
  const torch::Tensor distribution = torch::tensor({{std::log(3.0f), 0.0f}, {0.0f, -1e4f}});
  const torch::Tensor kl = policy->PriorKl(obs, distribution);
  EXPECT_NEAR(kl[0].item<double>(), 0.75 * std::log(1.5) + 0.25 * std::log(0.5), 1e-6);
  EXPECT_NEAR(kl[1].item<double>(), 0.0, 1e-7);
  EXPECT_FALSE(CategoricalActorCritic(2, 2, 2, config)->HasPrior());
}

// A selector's prior says choice 1 (a logit of 4); the bandit pays choice 3. Without the KL term
// PPO leaves the prior for choice 3; with it, the policy stays nearer the prior.
TEST(Ppo, PriorKlKeepsTheSelectorNearItsPrior) {
  PolicyConfig config;
  config.actor_hidden = {16};
  config.critic_hidden = {16};
  torch::Tensor obs = torch::zeros({8, 32, 4 + 5});
  obs.narrow(2, 0, 4).copy_(torch::randn({8, 32, 4}));
  obs.select(2, 4 + 1).fill_(4.0f);
  auto choice3 = [](const torch::Tensor& actions) { return (actions.select(2, 0) == 3).to(torch::kFloat32); };
  auto train = [&](double coef, double& last_prior_kl) {
    torch::manual_seed(6);
    CategoricalActorCritic policy(9, 9, 5, config, 1, /*prior_logits=*/true);
    PpoConfig ppo_config;
    ppo_config.prior_kl_coef = coef;
    Ppo ppo(policy.ptr(), ppo_config);
    for (int update = 0; update < 30; ++update) {
      const Rollout r = BanditRollout(*policy, obs, choice3);
      const PpoStats stats = ppo.Update(r, ComputeReturns(r, torch::zeros({32}), 0.99, 0.95));
      EXPECT_TRUE(stats.finite);
      last_prior_kl = stats.prior_kl;
    }
    torch::NoGradGuard no_grad;
    return torch::softmax(policy->Distribution(obs), -1).select(2, 3).mean().item<double>();
  };
  double kl_free = 0.0, kl_held = 0.0;
  const double free = train(0.0, kl_free), held = train(1.0, kl_held);
  EXPECT_GT(free, 0.9);
  EXPECT_LT(held, 0.5);
  EXPECT_GT(kl_free, 4.0 * kl_held);
}

TEST(Ppo, PriorKlWithoutAPriorIsRefusedByName) {
  ActorCritic policy = TinyPolicy(4, 2);
  PpoConfig config;
  config.prior_kl_coef = 0.1;
  try {
    Ppo ppo(policy.ptr(), config);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ppo.prior_kl_coef"), std::string::npos) << e.what();
  }
}

// A NaN in the network makes the loss NaN: the update reports it and leaves the weights alone.
TEST(Ppo, NonFiniteLossTakesNoStep) {
  torch::manual_seed(5);
  ActorCritic policy = TinyPolicy(4, 2);
  Ppo ppo(policy.ptr(), PpoConfig{});
  const torch::Tensor obs = torch::randn({4, 8, 4});
  Rollout r = BanditRollout(*policy, obs, FirstActionPositive);
  r.rewards[0][0] = NAN;
  std::vector<torch::Tensor> before;
  for (const torch::Tensor& p : policy->parameters()) before.push_back(p.detach().clone());
  const PpoStats stats = ppo.Update(r, ComputeReturns(r, torch::zeros({8}), 0.99, 0.95));
  EXPECT_FALSE(stats.finite);
  const std::vector<torch::Tensor> after = policy->parameters();
  for (size_t i = 0; i < after.size(); ++i) EXPECT_TRUE(torch::equal(after[i], before[i])) << "parameter " << i;
}

// Mirror images that are copies of their originals repeat every sample once: the mean losses, and
// so the update, are those without them.
TEST(Ppo, MirrorImagesIdenticalToTheOriginalsLeaveTheUpdateAsItWas) {
  PpoConfig config;
  config.adaptive_learning_rate = false;
  torch::manual_seed(8);
  const torch::Tensor obs = torch::randn({4, 16, 4});
  std::vector<std::vector<torch::Tensor>> results;
  for (bool with_copies : {false, true}) {
    torch::manual_seed(9);
    ActorCritic policy = TinyPolicy(4, 2);
    Ppo ppo(policy.ptr(), config);
    const Rollout r = BanditRollout(*policy, obs, FirstActionPositive);
    const Returns returns = ComputeReturns(r, torch::zeros({16}), 0.99, 0.95);
    const MirroredSamples copies{r.obs.reshape({64, 4}), r.critic_obs.reshape({64, 4}), r.actions.reshape({64, 2})};
    torch::manual_seed(10);  // the same minibatches
    ASSERT_TRUE(ppo.Update(r, returns, with_copies ? &copies : nullptr).finite);
    std::vector<torch::Tensor> parameters;
    for (const torch::Tensor& p : policy->parameters()) parameters.push_back(p.detach().clone());
    results.push_back(parameters);
  }
  for (size_t i = 0; i < results[0].size(); ++i) {
    EXPECT_TRUE(torch::allclose(results[0][i], results[1][i], 1e-5, 1e-6)) << "parameter " << i;
  }
}

// A bandit seen only on one side (obs[0] > 0, where a positive action 0 pays) and its mirror
// image (obs[0] and action 0 negated): with the mirror images the policy learns the other side
// too, a negative action 0 where obs[0] < 0, which it never saw; without them it does not.
TEST(Ppo, MirrorImagesTeachTheSideTheRolloutsNeverSaw) {
  auto mean_action0_on_the_unseen_side = [](bool mirrored) {
    torch::manual_seed(11);
    ActorCritic policy = TinyPolicy(4, 2);
    Ppo ppo(policy.ptr(), PpoConfig{});
    torch::Tensor obs = torch::randn({8, 32, 4});
    obs.select(2, 0).abs_();
    const torch::Tensor flip = torch::tensor({-1.0f, 1.0f, 1.0f, 1.0f});
    const torch::Tensor flip_action = torch::tensor({-1.0f, 1.0f});
    for (int update = 0; update < 20; ++update) {
      const Rollout r = BanditRollout(*policy, obs, FirstActionPositive);
      const MirroredSamples images{r.obs.reshape({-1, 4}) * flip, r.critic_obs.reshape({-1, 4}) * flip,
                                   r.actions.reshape({-1, 2}) * flip_action};
      EXPECT_TRUE(ppo.Update(r, ComputeReturns(r, torch::zeros({32}), 0.99, 0.95), mirrored ? &images : nullptr).finite);
    }
    torch::NoGradGuard no_grad;
    return policy->ActionMean(obs * flip).select(2, 0).mean().item<double>();
  };
  EXPECT_LT(mean_action0_on_the_unseen_side(true), -0.5);
  EXPECT_GT(mean_action0_on_the_unseen_side(false), 0.0);
}

TEST(Ppo, SetLearningRateReachesTheOptimizer) {
  ActorCritic policy = TinyPolicy(4, 2);
  Ppo ppo(policy.ptr(), PpoConfig{});
  EXPECT_EQ(ppo.learning_rate(), PpoConfig{}.learning_rate);
  ppo.set_learning_rate(3e-4);
  EXPECT_EQ(ppo.learning_rate(), 3e-4);
  for (const auto& group : ppo.optimizer().param_groups()) {
    EXPECT_EQ(static_cast<const torch::optim::AdamOptions&>(group.options()).lr(), 3e-4);
  }
}

}  // namespace
}  // namespace flsd
