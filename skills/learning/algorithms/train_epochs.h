#pragma once
// Supervised minibatch epochs on the job's ranks together: how the PAE and the discriminator learn
// from a rollout.

#include <torch/torch.h>

#include <functional>

#include "skills/learning/runners/communicator.h"

namespace flsd {

// `epochs` passes over `samples` (row indices) in shuffled minibatches, one optimiser step each
// on loss_of(minibatch). Every rank of `comm` passes over its own samples, as many as the others,
// and the ranks step together on their averaged gradients: `minibatch` is the size of the ranks'
// minibatches together. Returns the mean loss over the ranks, or NaN, without stepping, as soon as
// a loss is not finite on any rank.
double TrainEpochs(torch::optim::Optimizer& optimizer, const Communicator& comm, const torch::Tensor& samples,
                   int epochs, int64_t minibatch, const std::function<torch::Tensor(const torch::Tensor&)>& loss_of);

}  // namespace flsd
