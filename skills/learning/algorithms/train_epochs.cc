#include "skills/learning/algorithms/train_epochs.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace flsd {
namespace {

bool Finite(const torch::Tensor& x) { return torch::isfinite(x).all().item<bool>(); }

std::vector<torch::Tensor> Parameters(const torch::optim::Optimizer& optimizer) {
  std::vector<torch::Tensor> all;
  for (const auto& group : optimizer.param_groups()) all.insert(all.end(), group.params().begin(), group.params().end());
  return all;
}

}  // namespace

double TrainEpochs(torch::optim::Optimizer& optimizer, const Communicator& comm, const torch::Tensor& samples,
                   int epochs, int64_t minibatch, const std::function<torch::Tensor(const torch::Tensor&)>& loss_of) {
  const int64_t n = samples.size(0);
  const int64_t share = std::max<int64_t>(1, minibatch / comm.size());
  const std::vector<torch::Tensor> parameters = Parameters(optimizer);
  double loss_sum = 0.0;
  int updates = 0;
  for (int epoch = 0; epoch < epochs; ++epoch) {
    const torch::Tensor order = samples.index_select(0, torch::randperm(n, torch::kLong));
    for (int64_t begin = 0; begin < n; begin += share) {
      const torch::Tensor loss = loss_of(order.slice(0, begin, std::min(n, begin + share)));
      if (comm.Any(!Finite(loss))) return NAN;
      optimizer.zero_grad();
      loss.backward();
      comm.AverageGradients(parameters);
      optimizer.step();
      loss_sum += loss.item<double>();
      ++updates;
    }
  }
  return updates > 0 ? comm.Sum(loss_sum / updates) / comm.size() : 0.0;
}

}  // namespace flsd
