#include "skills/learning/algorithms/ppo.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/check.h"

namespace flsd {
namespace {

torch::Tensor Flat(const torch::Tensor& x) {
  return x.dim() == 2 ? x.reshape({-1}) : x.reshape({-1, x.size(-1)});
}

// (raw - mean) / std over every rank's samples.
torch::Tensor Normalized(const torch::Tensor& raw, const Communicator& comm) {
  if (comm.size() == 1) return (raw - raw.mean()) / (raw.std() + 1e-8);
  // Mean and (unbiased) std over all ranks' transitions, from their sums.
  double moments[3] = {static_cast<double>(raw.numel()), raw.sum().item<double>(),
                       raw.to(torch::kFloat64).pow(2).sum().item<double>()};
  comm.Sum(moments, 3);
  const double mean = moments[1] / moments[0];
  const double std = std::sqrt(std::max(0.0, (moments[2] - moments[0] * mean * mean) / (moments[0] - 1.0)));
  return (raw - mean) / (std + 1e-8);
}

}  // namespace

Returns ComputeReturns(const Rollout& r, const torch::Tensor& last_values, double gamma, double lambda,
                       const Communicator& comm) {
  torch::NoGradGuard no_grad;
  const int64_t steps = r.rewards.size(0);
  const bool streams = r.values.dim() == 3;  // [T, N, S]: one return per reward stream
  const torch::Tensor dones = streams ? r.dones.unsqueeze(-1) : r.dones;
  const torch::Tensor rewards = r.rewards + gamma * r.values * (streams ? r.timeouts.unsqueeze(-1) : r.timeouts);
  Returns out;
  out.returns = torch::empty_like(rewards);
  torch::Tensor advantage = torch::zeros_like(last_values);
  torch::Tensor next_value = last_values;
  for (int64_t t = steps - 1; t >= 0; --t) {
    const torch::Tensor not_done = 1.0 - dones[t];
    const torch::Tensor delta = rewards[t] + gamma * next_value * not_done - r.values[t];
    advantage = delta + gamma * lambda * not_done * advantage;
    out.returns[t] = advantage + r.values[t];
    next_value = r.values[t];
  }
  const torch::Tensor raw = out.returns - r.values;
  if (!streams) {
    out.advantages = Normalized(raw, comm);
    return out;
  }
  // Each stream's advantages normalised on their own, then summed (ETH D3's multi-critic PPO): a
  // stream of large penalties cannot drown a stream of small rewards, nor a clip erase it.
  out.advantages = torch::zeros_like(raw.select(2, 0));
  for (int64_t s = 0; s < raw.size(2); ++s) out.advantages += Normalized(raw.select(2, s), comm);
  return out;
}

Ppo::Ppo(std::shared_ptr<PpoPolicyImpl> policy, const PpoConfig& config, const Communicator& comm)
    : policy_(std::move(policy)),
      config_(config),
      comm_(comm),
      optimizer_(policy_->parameters(), torch::optim::AdamOptions(config.learning_rate)),
      learning_rate_(config.learning_rate) {
  if (config_.prior_kl_coef > 0.0 && !policy_->HasPrior()) {
    throw InputError("ppo.prior_kl_coef: " + std::to_string(config_.prior_kl_coef) +
                     " pulls the policy toward its prior, but this policy has none (a selector with "
                     "time_sharing_prior or nearest_prior_temperature has); expected 0");
  }
}

void Ppo::set_learning_rate(double lr) {
  learning_rate_ = lr;
  for (auto& group : optimizer_.param_groups()) {
    static_cast<torch::optim::AdamOptions&>(group.options()).lr(lr);
  }
}

PpoStats Ppo::Update(const Rollout& rollout, const Returns& returns, const MirroredSamples* mirrored) {
  const torch::Tensor obs = Flat(rollout.obs), critic_obs = Flat(rollout.critic_obs);
  const torch::Tensor actions = Flat(rollout.actions), old_distributions = Flat(rollout.distributions);
  const torch::Tensor old_log_probs = Flat(rollout.log_probs), old_values = Flat(rollout.values);
  const torch::Tensor target = Flat(returns.returns), advantages = Flat(returns.advantages);
  const int64_t batch = obs.size(0);
  const int64_t minibatch = std::max<int64_t>(1, batch / config_.minibatches);

  PpoStats stats;
  int updates = 0;
  for (int epoch = 0; epoch < config_.epochs; ++epoch) {
    const torch::Tensor order = torch::randperm(batch, torch::kLong);
    for (int64_t begin = 0; begin + minibatch <= batch; begin += minibatch) {
      const torch::Tensor idx = order.slice(0, begin, begin + minibatch);
      // With mirror images, the minibatch is [originals; mirror images], and what the mirror
      // images take from their originals is repeated.
      auto with_mirror = [&](const torch::Tensor& all, const torch::Tensor* mirrored_all) {
        const torch::Tensor picked = all.index_select(0, idx);
        return mirrored_all ? torch::cat({picked, mirrored_all->index_select(0, idx)}, 0) : picked;
      };
      auto repeated = [&](const torch::Tensor& all) { return with_mirror(all, mirrored ? &all : nullptr); };
      const torch::Tensor distributions = policy_->Distribution(with_mirror(obs, mirrored ? &mirrored->obs : nullptr));
      const torch::Tensor distribution = distributions.slice(0, 0, minibatch);  // the originals'
      const torch::Tensor value = policy_->Value(with_mirror(critic_obs, mirrored ? &mirrored->critic_obs : nullptr));

      if (config_.adaptive_learning_rate) {
        torch::NoGradGuard no_grad;
        const double kl_value =
            comm_.Sum(policy_->Kl(old_distributions.index_select(0, idx), distribution).mean().item<double>()) /
            comm_.size();
        stats.kl += kl_value;
        if (kl_value > 2.0 * config_.desired_kl) {
          set_learning_rate(std::max(1e-5, learning_rate_ / 1.5));
        } else if (kl_value > 0.0 && kl_value < 0.5 * config_.desired_kl) {
          set_learning_rate(std::min(1e-2, learning_rate_ * 1.5));
        }
      }

      const torch::Tensor log_prob =
          policy_->LogProb(distributions, with_mirror(actions, mirrored ? &mirrored->actions : nullptr));
      const torch::Tensor ratio = torch::exp(log_prob - repeated(old_log_probs));
      const torch::Tensor adv = repeated(advantages);
      const torch::Tensor surrogate =
          torch::max(-adv * ratio, -adv * torch::clamp(ratio, 1.0 - config_.clip, 1.0 + config_.clip)).mean();
      const torch::Tensor mb_old_values = repeated(old_values);
      const torch::Tensor mb_target = repeated(target);
      const torch::Tensor value_clipped =
          mb_old_values + torch::clamp(value - mb_old_values, -config_.clip, config_.clip);
      const torch::Tensor value_loss =
          torch::max((value - mb_target).pow(2), (value_clipped - mb_target).pow(2)).mean();
      const torch::Tensor entropy = policy_->Entropy(distribution).mean();
      const torch::Tensor prior_kl = policy_->HasPrior()
                                         ? policy_->PriorKl(obs.index_select(0, idx), distribution).mean()
                                         : torch::zeros({});
      const torch::Tensor loss = surrogate + config_.value_coef * value_loss - config_.entropy_coef * entropy +
                                 config_.prior_kl_coef * prior_kl;

      if (comm_.Any(!torch::isfinite(loss).item<bool>())) {
        stats.finite = false;
        return stats;
      }
      optimizer_.zero_grad();
      loss.backward();
      comm_.AverageGradients(policy_->parameters());
      torch::nn::utils::clip_grad_norm_(policy_->parameters(), config_.max_grad_norm);
      optimizer_.step();

      stats.surrogate_loss += surrogate.item<double>();
      stats.value_loss += value_loss.item<double>();
      stats.entropy += entropy.item<double>();
      stats.prior_kl += prior_kl.item<double>();
      ++updates;
    }
  }
  if (updates > 0) {
    double losses[4] = {stats.surrogate_loss, stats.value_loss, stats.entropy, stats.prior_kl};
    comm_.Sum(losses, 4);  // the mean over the ranks' minibatches
    stats.surrogate_loss = losses[0] / (updates * comm_.size());
    stats.value_loss = losses[1] / (updates * comm_.size());
    stats.entropy = losses[2] / (updates * comm_.size());
    stats.prior_kl = losses[3] / (updates * comm_.size());
    stats.kl /= updates;
  }
  stats.learning_rate = learning_rate_;
  return stats;
}

}  // namespace flsd
