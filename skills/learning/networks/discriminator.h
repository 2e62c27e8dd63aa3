#pragma once
// The skill discriminator q(k | o^d) of Eqs. 10-12.

#include <torch/torch.h>

#include <vector>

#include "core/config.h"

namespace flsd {

struct DiscriminatorConfig {
  std::vector<int> hidden{128, 128};
  double learning_rate = 1e-4;  // Adam, as ETH D3's DIAYN discriminator
  int epochs = 1;
  int minibatch_size = 1024;
  // The discriminator trains on inputs blurred by Gaussian noise of these standard deviations: q
  // (metres) and the motion features after it (P, or DIAYN's o^m). Rewards read clean inputs. A
  // skill is then told apart only once it differs by more than the blur: creeping 0.1 m from the
  // others earns nothing, travelling further earns more until the skills are clear of one another.
  double position_noise = 0.0;
  double feature_noise = 0.0;
  // q also holds the heading the robot has turned through since its skill began (rad, unwrapped,
  // blurred as the position is): turning in place then goes somewhere as walking does, and a left
  // turn is told apart from a right one. The paper's q is the position alone.
  bool heading = false;
  // Columns of q: x, y and, with heading, the heading turned.
  int skill_frame_size() const { return heading ? 3 : 2; }
  template <class V>
  void Visit(V& v) {
    v("hidden", hidden, Bounds<int>{1, 4096});
    v("learning_rate", learning_rate, Bounds<double>{0.0, 1.0});
    v("epochs", epochs, Bounds<int>{0, 1000});
    v("minibatch_size", minibatch_size, Bounds<int>{1, 1 << 20});
    v("position_noise", position_noise, Bounds<double>{0.0, 100.0});
    v("feature_noise", feature_noise, Bounds<double>{0.0, 100.0});
    v("heading", heading);
  }
};

class DiscriminatorImpl : public torch::nn::Module {
 public:
  DiscriminatorImpl(int inputs, int num_skills, const DiscriminatorConfig& config);
  // log q(k | o^d) for every k: [B, N_k].
  torch::Tensor LogProbs(const torch::Tensor& observations) {
    return torch::log_softmax(mlp_->forward(observations), -1);
  }
  int num_skills() const { return num_skills_; }

 private:
  torch::nn::Sequential mlp_{nullptr};
  int num_skills_;
};
TORCH_MODULE(Discriminator);

// o^d = [q (2), features] with the config's noise added to each part.
torch::Tensor Blurred(const torch::Tensor& observations, const DiscriminatorConfig& config);

// Eq. 12: the negative log-likelihood -E[log q(k | o^d)].
torch::Tensor DiscriminatorLoss(const torch::Tensor& log_probs, const torch::Tensor& skills);

}  // namespace flsd
