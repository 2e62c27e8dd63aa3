#include "bench/policy_bench.h"

#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>
#include <torch/torch.h>

#include <chrono>
#include <thread>

#include "bench/machine.h"
#include "bench/stats.h"
#include "core/paths.h"
#include "robot/observation.h"
#include "server/control_loop.h"
#include "server/controller.h"
#include "sim/sim_backend.h"
#include "skills/runtime/skill_library.h"

namespace flsd {
namespace {

using Clock = std::chrono::steady_clock;

// The library's policy as libtorch modules: Linear layers with its weights, ELU between them.
struct TorchPolicy {
  std::vector<torch::nn::Linear> layers;
  torch::Tensor mean, std;

  explicit TorchPolicy(const DenseNetwork& network) {
    for (const DenseLayer& l : network.layers) {
      torch::nn::Linear linear(torch::nn::LinearOptions(l.weight.cols(), l.weight.rows()));
      torch::NoGradGuard no_grad;
      linear->weight.copy_(torch::from_blob(const_cast<float*>(l.weight.data()), {l.weight.rows(), l.weight.cols()}));
      linear->bias.copy_(torch::from_blob(const_cast<float*>(l.bias.data()), {l.bias.size()}));
      layers.push_back(linear);
    }
    mean = torch::from_blob(const_cast<float*>(network.normalizer_mean.data()), {network.normalizer_mean.size()}).clone();
    std = torch::from_blob(const_cast<float*>(network.normalizer_std.data()), {network.normalizer_std.size()}).clone();
  }

  torch::Tensor Forward(const torch::Tensor& obs) {
    const int64_t n = mean.size(0);
    torch::Tensor x = torch::cat({(obs.slice(1, 0, n) - mean) / std, obs.slice(1, n)}, 1);
    for (size_t i = 0; i < layers.size(); ++i) {
      x = layers[i]->forward(x);
      if (i + 1 < layers.size()) x = torch::elu(x);
    }
    return x;
  }
};

double MicrosecondsPerCall(Clock::duration elapsed, int calls) {
  return std::chrono::duration<double, std::micro>(elapsed).count() / calls;
}

// The floor under any control loop on this machine: a thread that does nothing but sleep until
// the next 20 ms deadline, with the same scheduling as skilld's loop. Returns its lateness p99, s.
double BareSleepJitterP99(double seconds, int priority) {
  std::vector<double> lateness;
  std::thread sleeper([&] {
    prctl(PR_SET_TIMERSLACK, 1UL);
    if (priority > 0) {
      sched_param param{};
      param.sched_priority = priority;
      pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    }
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a1::kControlDt));
    auto next = Clock::now();
    const auto end = next + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
    while (next < end) {
      next += period;
      std::this_thread::sleep_until(next);
      lateness.push_back(std::chrono::duration<double>(Clock::now() - next).count());
    }
  });
  sleeper.join();
  return Quantile(lateness, 0.99);
}

nlohmann::json MeasureControlLoop(const SkillLibrary& library, double seconds) {
  ServerConfig config;
  SimBackend backend(config.sim);
  Controller controller(backend, library, config);
  ControlLoop loop(controller, config.control_priority, config.cpu_latency_us);
  ControlRequest skill;
  skill.kind = ControlRequest::Kind::kSkill;
  skill.skill = 0;
  skill.duration = seconds;
  controller.Submit(skill);
  loop.Start();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  const bool cpu_latency_held = loop.cpu_latency_held();
  loop.Stop();
  double bare_p99 = 0.0;
  {
    const CpuLatencyRequest same_as_loop(config.cpu_latency_us);
    bare_p99 = BareSleepJitterP99(seconds, config.control_priority);
  }
  return {{"ticks", loop.ticks()},
          {"bare_sleep_jitter_p99_ms", bare_p99 * 1e3},
          {"sched_fifo", loop.realtime()},
          {"cpu_dma_latency_held", cpu_latency_held},
          {"tick_lateness_p50_ms", loop.LatenessQuantile(0.5) * 1e3},
          {"tick_jitter_p99_ms", loop.LatenessQuantile(0.99) * 1e3},
          {"tick_lateness_max_ms", loop.worst_lateness() * 1e3},
          {"deadline_misses", loop.deadline_misses()},
          {"target_jitter_p99_ms_below", 1.0}};
}

}  // namespace

nlohmann::json RunPolicyBenchmark(const PolicyBenchOptions& options) {
  const SkillLibrary library = SkillLibrary::Load(ResolveDataPath(options.library));
  // Skill 0 on random motion and previous action: skilld's path, from o^m to the action.
  torch::manual_seed(1);
  const torch::Tensor motion = torch::randn({kMotionObsSize});
  const torch::Tensor previous = torch::randn({kActionSize});
  const SkillDescriptor& skill = library.skills()[0];
  const SkillPolicy& policy = library.policies()[skill.policy];
  const torch::Tensor obs = torch::zeros({1, PolicyObservationSize(policy.num_skills)});
  BuildPolicyObservation(motion.data_ptr<float>(), previous.data_ptr<float>(), skill.policy_skill, policy.num_skills,
                         obs.data_ptr<float>());

  PolicyRunner runner(library);
  std::array<float, kActionSize> action{};
  auto act = [&] { runner.Act(motion.data_ptr<float>(), previous.data_ptr<float>(), 0, action.data()); };
  for (int i = 0; i < 100; ++i) act();
  auto start = Clock::now();
  for (int i = 0; i < options.calls; ++i) act();
  const double eigen_us = MicrosecondsPerCall(Clock::now() - start, options.calls);

  torch::set_num_threads(1);  // one observation: threads only add hand-off cost
  torch::NoGradGuard no_grad;
  TorchPolicy torch_policy(policy.network);
  torch::Tensor torch_action;
  const int torch_calls = std::max(1, options.calls / 10);
  for (int i = 0; i < 50; ++i) torch_action = torch_policy.Forward(obs);
  start = Clock::now();
  for (int i = 0; i < torch_calls; ++i) torch_action = torch_policy.Forward(obs);
  const double torch_us = MicrosecondsPerCall(Clock::now() - start, torch_calls);

  double max_difference = 0.0;
  for (int j = 0; j < kActionSize; ++j) {
    max_difference = std::max(max_difference, static_cast<double>(std::abs(action[j] - torch_action[0][j].item<float>())));
  }
  return {{"benchmark", "flsd bench policy"},
          {"library", library.path()},
          {"eigen_us_per_tick", eigen_us},
          {"libtorch_us_per_tick", torch_us},
          {"speedup", torch_us / eigen_us},
          {"target_speedup_at_least", 5.0},
          {"max_action_difference", max_difference},
          {"control_loop", MeasureControlLoop(library, options.loop_seconds)},
          {"machine", MachineDescription()}};
}

}  // namespace flsd
