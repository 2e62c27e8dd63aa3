#include "skills/learning/networks/mlp.h"

namespace flsd {

torch::nn::Sequential MakeMlp(int inputs, const std::vector<int>& hidden, int outputs) {
  torch::nn::Sequential mlp;
  int width = inputs;
  for (int h : hidden) {
    mlp->push_back(torch::nn::Linear(width, h));
    mlp->push_back(torch::nn::ELU());
    width = h;
  }
  mlp->push_back(torch::nn::Linear(width, outputs));
  return mlp;
}

}  // namespace flsd
