#include "skills/learning/discriminator.h"

#include <cmath>

#include "skills/learning/mlp.h"

namespace flsd {

DiscriminatorImpl::DiscriminatorImpl(int inputs, int num_skills, const DiscriminatorConfig& config)
    : num_skills_(num_skills) {
  mlp_ = register_module("mlp", MakeMlp(inputs, config.hidden, num_skills));
}

torch::Tensor IntrinsicReward(const torch::Tensor& log_probs, const torch::Tensor& skills) {
  return log_probs.gather(1, skills.unsqueeze(1)).squeeze(1) + std::log(static_cast<double>(log_probs.size(1)));
}

torch::Tensor DiscriminatorLoss(const torch::Tensor& log_probs, const torch::Tensor& skills) {
  return torch::nll_loss(log_probs, skills);
}

}  // namespace flsd
