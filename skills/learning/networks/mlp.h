#pragma once
#include <torch/torch.h>

#include <vector>

namespace flsd {

// Linear layers of the given hidden widths with ELU between them and a linear output layer.
torch::nn::Sequential MakeMlp(int inputs, const std::vector<int>& hidden, int outputs);

}  // namespace flsd
