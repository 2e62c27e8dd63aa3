#pragma once
// Proximal Policy Optimisation as rsl_rl v1.0.2 does it (rsl_rl/algorithms/ppo.py): clipped
// surrogate, clipped value loss, entropy bonus, GAE(lambda) with a time-out bootstrap,
// advantages normalised over the whole batch, gradient-norm clipping, and a learning rate adapted
// from the KL divergence between the collecting and the updated policy.

#include <torch/torch.h>

#include "core/config.h"
#include "skills/learning/networks/actor_critic.h"
#include "skills/learning/runners/communicator.h"

namespace flsd {

struct PpoConfig {
  int epochs = 5;
  int minibatches = 4;
  double clip = 0.2;
  double value_coef = 1.0;
  double entropy_coef = 0.01;
  double learning_rate = 1e-3;
  bool adaptive_learning_rate = true;
  double desired_kl = 0.01;
  double gamma = 0.99;
  double lambda = 0.95;
  double max_grad_norm = 1.0;
  // Not rsl_rl's; 0 turns it off. The loss also carries this times KL(policy || its prior) (a
  // selector whose logits are added to a prior's, PpoPolicyImpl::PriorKl): the policy may improve
  // on the prior only where that pays more than it costs.
  double prior_kl_coef = 0.0;
  template <class V>
  void Visit(V& v) {
    v("epochs", epochs, Bounds<int>{1, 100});
    v("minibatches", minibatches, Bounds<int>{1, 1024});
    v("clip", clip, Bounds<double>{0.0, 1.0});
    v("value_coef", value_coef, Bounds<double>{0.0, 100.0});
    v("entropy_coef", entropy_coef, Bounds<double>{0.0, 10.0});
    v("learning_rate", learning_rate, Bounds<double>{1e-7, 1.0});
    v("adaptive_learning_rate", adaptive_learning_rate);
    v("desired_kl", desired_kl, Bounds<double>{1e-5, 1.0});
    v("gamma", gamma, Bounds<double>{0.0, 1.0});
    v("lambda", lambda, Bounds<double>{0.0, 1.0});
    v("max_grad_norm", max_grad_norm, Bounds<double>{0.0, 1000.0});
    v("prior_kl_coef", prior_kl_coef, Bounds<double>{0.0, 100.0});
  }
};

// One iteration's transitions; tensors are [T, N, ...] (steps x envs).
struct Rollout {
  torch::Tensor obs;         // normalised policy observations
  torch::Tensor critic_obs;  // critic observations
  torch::Tensor actions;
  torch::Tensor log_probs;      // [T, N]
  torch::Tensor values;         // [T, N], or [T, N, S] for S reward streams
  torch::Tensor distributions;  // [T, N, P], the collecting policy's (PpoPolicyImpl::Distribution)
  torch::Tensor rewards;     // [T, N], or [T, N, S] for S reward streams
  torch::Tensor dones;       // [T, N], 1 where the episode ended after step t (time-outs too)
  torch::Tensor timeouts;    // [T, N], 1 where it ended by time-out
};

// The rollout's mirror images (robot/mirror.h) for symmetry augmentation, flattened [T * N, ...]:
// what the policy would see and do in the mirrored world.
struct MirroredSamples {
  torch::Tensor obs;
  torch::Tensor critic_obs;
  torch::Tensor actions;
};

struct Returns {
  torch::Tensor returns;     // as the rollout's values
  torch::Tensor advantages;  // [T, N], normalised over the batch (each stream's, then summed)
};

// GAE(lambda) returns and advantages; last_values [N] are V of the observations after the last
// step. On a time-out, gamma V(s_t) is added to r_t, as rsl_rl does, since the episode did not
// really end there. Advantages are normalised over the batch of every rank in `comm`; with S
// reward streams (values and rewards [T, N, S], last_values [N, S]) each stream's are normalised
// on its own and the S are summed.
Returns ComputeReturns(const Rollout& rollout, const torch::Tensor& last_values, double gamma, double lambda,
                       const Communicator& comm = Communicator::Self());

struct PpoStats {
  double surrogate_loss = 0.0;
  double value_loss = 0.0;
  double entropy = 0.0;
  double kl = 0.0;
  double prior_kl = 0.0;  // KL(policy || its prior) over the minibatches; 0 without a prior
  double learning_rate = 0.0;
  bool finite = true;  // false when a loss turned NaN or infinite; no step was taken then
};

// With several ranks in `comm`, each updates on its own share of the rollout: the ranks average
// their gradients before every step and their KL before adapting the learning rate, so all keep
// the same parameters and learning rate.
class Ppo {
 public:
  Ppo(std::shared_ptr<PpoPolicyImpl> policy, const PpoConfig& config, const Communicator& comm = Communicator::Self());

  // With `mirrored`, every minibatch is trained together with its mirror images, which take the
  // originals' old log-probabilities, values, returns and advantages (rsl_rl's symmetry
  // augmentation); the KL that adapts the learning rate and the entropy bonus are the originals'.
  PpoStats Update(const Rollout& rollout, const Returns& returns, const MirroredSamples* mirrored = nullptr);

  torch::optim::Adam& optimizer() { return optimizer_; }
  const torch::optim::Adam& optimizer() const { return optimizer_; }
  double learning_rate() const { return learning_rate_; }
  void set_learning_rate(double lr);

 private:
  std::shared_ptr<PpoPolicyImpl> policy_;
  PpoConfig config_;
  const Communicator& comm_;
  torch::optim::Adam optimizer_;
  double learning_rate_;
};

}  // namespace flsd
