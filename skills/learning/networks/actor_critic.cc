#include "skills/learning/networks/actor_critic.h"

#include <cmath>

#include "skills/learning/networks/mlp.h"

namespace flsd {

ActorCriticImpl::ActorCriticImpl(int actor_inputs, int critic_inputs, int actions, const PolicyConfig& config,
                                 int value_streams)
    : actions_(actions) {
  actor_ = register_module("actor", MakeMlp(actor_inputs, config.actor_hidden, actions));
  critic_ = register_module("critic", MakeMlp(critic_inputs, config.critic_hidden, value_streams));
  log_std_ = register_parameter("log_std", torch::full({actions}, std::log(config.init_std)));
}

torch::Tensor ActorCriticImpl::Distribution(const torch::Tensor& obs) {
  const torch::Tensor mean = ActionMean(obs);
  return torch::cat({mean, Std().expand_as(mean)}, -1);
}

torch::Tensor ActorCriticImpl::LogProb(const torch::Tensor& distribution, const torch::Tensor& actions) const {
  const torch::Tensor mean = distribution.slice(-1, 0, actions_), std = distribution.slice(-1, actions_);
  const torch::Tensor z = (actions - mean) / std;
  return (-0.5 * z.pow(2) - std.log() - 0.5 * std::log(2.0 * M_PI)).sum(-1);
}

torch::Tensor ActorCriticImpl::Entropy(const torch::Tensor& distribution) const {
  return (distribution.slice(-1, actions_).log() + 0.5 * (1.0 + std::log(2.0 * M_PI))).sum(-1);
}

torch::Tensor ActorCriticImpl::Kl(const torch::Tensor& old_distribution, const torch::Tensor& distribution) const {
  const torch::Tensor old_mean = old_distribution.slice(-1, 0, actions_), old_std = old_distribution.slice(-1, actions_);
  const torch::Tensor mean = distribution.slice(-1, 0, actions_), std = distribution.slice(-1, actions_);
  return (torch::log(std / old_std) + (old_std.pow(2) + (old_mean - mean).pow(2)) / (2.0 * std.pow(2)) - 0.5).sum(-1);
}

torch::Tensor ActorCriticImpl::Sample(const torch::Tensor& distribution) const {
  const torch::Tensor mean = distribution.slice(-1, 0, actions_), std = distribution.slice(-1, actions_);
  return (mean + std * torch::randn_like(mean)).contiguous();
}

CategoricalActorCriticImpl::CategoricalActorCriticImpl(int actor_inputs, int critic_inputs, int choices,
                                                       const PolicyConfig& config, int value_streams, bool prior_logits)
    : prior_(prior_logits ? choices : 0) {
  actor_ = register_module("actor", MakeMlp(actor_inputs - prior_, config.actor_hidden, choices));
  critic_ = register_module("critic", MakeMlp(critic_inputs - prior_, config.critic_hidden, value_streams));
}

torch::Tensor CategoricalActorCriticImpl::Distribution(const torch::Tensor& obs) {
  const torch::Tensor logits = actor_->forward(WithoutPrior(obs));
  return prior_ > 0 ? logits + obs.narrow(-1, obs.size(-1) - prior_, prior_) : logits;
}

torch::Tensor CategoricalActorCriticImpl::Value(const torch::Tensor& critic_obs) {
  return StreamValues(critic_->forward(WithoutPrior(critic_obs)));
}

torch::Tensor CategoricalActorCriticImpl::LogProb(const torch::Tensor& distribution, const torch::Tensor& actions) const {
  return torch::log_softmax(distribution, -1).gather(-1, actions.to(torch::kLong)).squeeze(-1);
}

torch::Tensor CategoricalActorCriticImpl::Entropy(const torch::Tensor& distribution) const {
  const torch::Tensor log_p = torch::log_softmax(distribution, -1);
  return -(log_p.exp() * log_p).sum(-1);
}

torch::Tensor CategoricalActorCriticImpl::Kl(const torch::Tensor& old_distribution,
                                             const torch::Tensor& distribution) const {
  const torch::Tensor old_log_p = torch::log_softmax(old_distribution, -1);
  return (old_log_p.exp() * (old_log_p - torch::log_softmax(distribution, -1))).sum(-1);
}

torch::Tensor CategoricalActorCriticImpl::PriorKl(const torch::Tensor& obs, const torch::Tensor& distribution) const {
  // Masked choices carry -1e4 in both: probability 0 times a finite log-ratio adds nothing.
  return Kl(distribution, obs.narrow(-1, obs.size(-1) - prior_, prior_));
}

torch::Tensor CategoricalActorCriticImpl::Sample(const torch::Tensor& distribution) const {
  // multinomial takes at most 2-D input: flatten the leading dimensions and restore them.
  const torch::Tensor flat = torch::softmax(distribution, -1).reshape({-1, distribution.size(-1)});
  std::vector<int64_t> shape(distribution.sizes().begin(), distribution.sizes().end());
  shape.back() = 1;
  return torch::multinomial(flat, 1).to(torch::kFloat32).reshape(shape);
}

}  // namespace flsd
