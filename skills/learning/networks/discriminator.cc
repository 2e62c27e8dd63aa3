#include "skills/learning/networks/discriminator.h"

#include <cmath>

#include "skills/learning/networks/mlp.h"

namespace flsd {

DiscriminatorImpl::DiscriminatorImpl(int inputs, int num_skills, const DiscriminatorConfig& config)
    : num_skills_(num_skills) {
  mlp_ = register_module("mlp", MakeMlp(inputs, config.hidden, num_skills));
}

torch::Tensor Blurred(const torch::Tensor& observations, const DiscriminatorConfig& config) {
  if (config.position_noise == 0.0 && config.feature_noise == 0.0) return observations;
  torch::Tensor scale = torch::full({observations.size(1)}, config.feature_noise, observations.options());
  scale.slice(0, 0, config.skill_frame_size()).fill_(config.position_noise);
  return observations + torch::randn_like(observations) * scale;
}

torch::Tensor DiscriminatorLoss(const torch::Tensor& log_probs, const torch::Tensor& skills) {
  return torch::nll_loss(log_probs, skills);
}

}  // namespace flsd
