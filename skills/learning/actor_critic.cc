#include "skills/learning/actor_critic.h"

#include <cmath>

#include "skills/learning/mlp.h"

namespace flsd {

ActorCriticImpl::ActorCriticImpl(int actor_inputs, int critic_inputs, int actions, const PolicyConfig& config) {
  actor_ = register_module("actor", MakeMlp(actor_inputs, config.actor_hidden, actions));
  critic_ = register_module("critic", MakeMlp(critic_inputs, config.critic_hidden, 1));
  log_std_ = register_parameter("log_std", torch::full({actions}, std::log(config.init_std)));
}

torch::Tensor ActorCriticImpl::LogProb(const torch::Tensor& mean, const torch::Tensor& actions) const {
  const torch::Tensor z = (actions - mean) / Std();
  return (-0.5 * z.pow(2) - log_std_ - 0.5 * std::log(2.0 * M_PI)).sum(-1);
}

torch::Tensor ActorCriticImpl::Entropy() const {
  return (log_std_ + 0.5 * (1.0 + std::log(2.0 * M_PI))).sum();
}

}  // namespace flsd
