#pragma once
#include <torch/torch.h>

#include <vector>

#include "core/config.h"

namespace flsd {

struct PolicyConfig {
  std::vector<int> actor_hidden{128, 64};
  std::vector<int> critic_hidden{128, 64};
  double init_std = 1.0;  // rsl_rl's init_noise_std
  template <class V>
  void Visit(V& v) {
    v("actor_hidden", actor_hidden, Bounds<int>{1, 4096});
    v("critic_hidden", critic_hidden, Bounds<int>{1, 4096});
    v("init_std", init_std, Bounds<double>{1e-3, 10.0});
  }
};

// A Gaussian policy with a state-independent, learned standard deviation, and a value function.
class ActorCriticImpl : public torch::nn::Module {
 public:
  ActorCriticImpl(int actor_inputs, int critic_inputs, int actions, const PolicyConfig& config);

  torch::Tensor ActionMean(const torch::Tensor& obs) { return actor_->forward(obs); }
  torch::Tensor Value(const torch::Tensor& critic_obs) { return critic_->forward(critic_obs).squeeze(-1); }
  torch::Tensor Std() const { return log_std_.exp(); }
  // Sum over action dimensions of the Gaussian log density of `actions`.
  torch::Tensor LogProb(const torch::Tensor& mean, const torch::Tensor& actions) const;
  // Entropy of the (state-independent) action distribution.
  torch::Tensor Entropy() const;

  torch::nn::Sequential actor() const { return actor_; }

 private:
  torch::nn::Sequential actor_{nullptr}, critic_{nullptr};
  torch::Tensor log_std_;
};
TORCH_MODULE(ActorCritic);

}  // namespace flsd
