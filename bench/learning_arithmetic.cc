#include "bench/learning_arithmetic.h"

#include <chrono>

namespace flsd {
namespace {

constexpr double kForwardAndBackward = 3.0;  // a backward pass costs about twice its forward

// Multiply-accumulates of one sample through every linear layer of `module`.
double LinearMacs(const torch::nn::Module& module) {
  double macs = 0.0;
  for (const auto& m : module.modules(/*include_self=*/true)) {
    if (const auto* linear = m->as<torch::nn::Linear>()) macs += static_cast<double>(linear->weight.numel());
  }
  return macs;
}

}  // namespace

LearningArithmetic ArithmeticOfLastIteration(const SkillDiscoveryTask& task) {
  const TrainConfig& config = task.config();
  const RolloutShape shape = task.shape();
  const double steps = static_cast<double>(shape.steps) * shape.envs;
  const double copies = task.mirrored() ? 2.0 : 1.0;  // originals and their mirror images
  const double policy = LinearMacs(*task.actor_critic());
  const double discriminator = LinearMacs(*task.discriminator());
  constexpr double kGiga = 1e-9, kFlopsPerMac = 2.0;

  LearningArithmetic a;
  a.policy_inference = kGiga * kFlopsPerMac * steps * policy;
  const int64_t minibatch = static_cast<int64_t>(steps) / config.ppo.minibatches;
  a.ppo_update = kGiga * kFlopsPerMac * kForwardAndBackward * config.ppo.epochs * config.ppo.minibatches *
                 minibatch * copies * policy;
  a.discriminator_update = kGiga * kFlopsPerMac * kForwardAndBackward * config.discriminator.epochs *
                           task.discriminator_samples() * discriminator;
  double encoding = 0.0;
  if (task.method() == Method::kFlsd) {
    const MotionStreamFrames& w = task.motion_windows();
    encoding = copies * task.pae()->ManifoldAlongMacs(w.frames.size(1), w.ends.size(0));
    const double sampled = std::max<double>(1.0, std::llround(config.pae.sample_fraction * steps));
    a.pae_update = kGiga * kFlopsPerMac * kForwardAndBackward * config.pae.epochs * sampled *
                   task.pae()->ForwardMacsPerWindow();
  }
  a.rewards = kGiga * kFlopsPerMac * (encoding + steps * discriminator);
  return a;
}

double MeasureSgemmGflops(int n, double seconds) {
  torch::NoGradGuard no_grad;
  const torch::Tensor a = torch::randn({n, n}), b = torch::randn({n, n});
  torch::Tensor c = torch::mm(a, b);  // warm-up: the BLAS's buffers and threads
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  int64_t calls = 0;
  double elapsed = 0.0;
  while (elapsed < seconds) {
    torch::mm_out(c, a, b);
    ++calls;
    elapsed = std::chrono::duration<double>(Clock::now() - start).count();
  }
  return 2.0 * n * n * n * calls / elapsed / 1e9;
}

}  // namespace flsd
