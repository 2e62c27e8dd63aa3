#pragma once

#include <torch/torch.h>

#include <stdexcept>
#include <vector>

#include "core/config.h"

namespace flsd {

struct PolicyConfig {
  std::vector<int> actor_hidden{128, 64};
  std::vector<int> critic_hidden{128, 64};
  double init_std = 1.0;  // rsl_rl's init_noise_std (Gaussian policies only)
  template <class V>
  void Visit(V& v) {
    v("actor_hidden", actor_hidden, Bounds<int>{1, 4096});
    v("critic_hidden", critic_hidden, Bounds<int>{1, 4096});
    v("init_std", init_std, Bounds<double>{1e-3, 10.0});
  }
};

// A critic's output [B, S] as Value returns it: [B] for one stream.
inline torch::Tensor StreamValues(const torch::Tensor& out) { return out.size(-1) == 1 ? out.squeeze(-1) : out; }

// What PPO needs of an actor-critic, whatever its action distribution. A distribution is passed
// around as one tensor of parameters per sample (what the rollout keeps of the collecting policy),
// so that PPO can compare the collecting and the updated policy without knowing their kind.
class PpoPolicyImpl : public torch::nn::Module {
 public:
  // The action distribution's parameters for each row of obs [B, ...]: [B, P].
  virtual torch::Tensor Distribution(const torch::Tensor& obs) = 0;
  // [B], or [B, S] for a critic of S > 1 value streams (one per reward stream).
  virtual torch::Tensor Value(const torch::Tensor& critic_obs) = 0;
  // Per sample: log density of `actions`, entropy, and KL(old || new).
  virtual torch::Tensor LogProb(const torch::Tensor& distribution, const torch::Tensor& actions) const = 0;
  virtual torch::Tensor Entropy(const torch::Tensor& distribution) const = 0;
  virtual torch::Tensor Kl(const torch::Tensor& old_distribution, const torch::Tensor& distribution) const = 0;
  // One action per row, drawn from the distribution (for collecting rollouts).
  virtual torch::Tensor Sample(const torch::Tensor& distribution) const = 0;
  // Whether the policy's distribution is a learned correction of a prior carried in obs; with one,
  // per sample KL(policy || prior).
  virtual bool HasPrior() const { return false; }
  virtual torch::Tensor PriorKl(const torch::Tensor& /*obs*/, const torch::Tensor& /*distribution*/) const {
    throw std::logic_error("PriorKl: this policy has no prior");
  }
};

// A Gaussian policy with a state-independent, learned standard deviation, and a value function.
// Its distribution tensor is [mean (A), std (A)].
class ActorCriticImpl : public PpoPolicyImpl {
 public:
  ActorCriticImpl(int actor_inputs, int critic_inputs, int actions, const PolicyConfig& config,
                  int value_streams = 1);

  torch::Tensor ActionMean(const torch::Tensor& obs) { return actor_->forward(obs); }
  torch::Tensor Std() const { return log_std_.exp(); }

  torch::Tensor Distribution(const torch::Tensor& obs) override;
  torch::Tensor Value(const torch::Tensor& critic_obs) override { return StreamValues(critic_->forward(critic_obs)); }
  torch::Tensor LogProb(const torch::Tensor& distribution, const torch::Tensor& actions) const override;
  torch::Tensor Entropy(const torch::Tensor& distribution) const override;
  torch::Tensor Kl(const torch::Tensor& old_distribution, const torch::Tensor& distribution) const override;
  torch::Tensor Sample(const torch::Tensor& distribution) const override;

  torch::nn::Sequential actor() const { return actor_; }

 private:
  int actions_;
  torch::nn::Sequential actor_{nullptr}, critic_{nullptr};
  torch::Tensor log_std_;
};
TORCH_MODULE(ActorCritic);

// A categorical policy over `choices` (the skill selector): its distribution tensor is the
// logits, its action the chosen index as a float column [B, 1]. With `prior_logits`, each
// observation row ends in `choices` prior logits (NearestSkillSelector::Prior) that the actor's
// logits are added to; the networks read the columns before them.
class CategoricalActorCriticImpl : public PpoPolicyImpl {
 public:
  CategoricalActorCriticImpl(int actor_inputs, int critic_inputs, int choices, const PolicyConfig& config,
                             int value_streams = 1, bool prior_logits = false);

  torch::Tensor Distribution(const torch::Tensor& obs) override;
  torch::Tensor Value(const torch::Tensor& critic_obs) override;
  torch::Tensor LogProb(const torch::Tensor& distribution, const torch::Tensor& actions) const override;
  torch::Tensor Entropy(const torch::Tensor& distribution) const override;
  torch::Tensor Kl(const torch::Tensor& old_distribution, const torch::Tensor& distribution) const override;
  torch::Tensor Sample(const torch::Tensor& distribution) const override;
  bool HasPrior() const override { return prior_ > 0; }
  torch::Tensor PriorKl(const torch::Tensor& obs, const torch::Tensor& distribution) const override;

  // Reads the observation without its prior columns (what is exported).
  torch::nn::Sequential actor() const { return actor_; }

 private:
  torch::Tensor WithoutPrior(const torch::Tensor& obs) const { return obs.narrow(-1, 0, obs.size(-1) - prior_); }

  int prior_;  // trailing prior columns: 0 or choices
  torch::nn::Sequential actor_{nullptr}, critic_{nullptr};
};
TORCH_MODULE(CategoricalActorCritic);

}  // namespace flsd
