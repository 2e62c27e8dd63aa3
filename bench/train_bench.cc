#include "bench/train_bench.h"

#include "bench/machine.h"
#include "bench/sim_bench.h"
#include "core/paths.h"
#include "skills/learning/trainer.h"
#include "skills/learning/training_run.h"

namespace flsd {

nlohmann::json RunTrainBenchmark(const TrainBenchOptions& options) {
  TrainConfig config = LoadTrainConfig(ResolveDataPath(options.config));
  if (!options.method.empty()) config.method = options.method;
  ConfigureTorchThreads(config.num_threads);
  Trainer trainer(config);
  trainer.RunIteration();  // warm-up: first-touch allocations in libtorch and the rollout

  IterationStats sum;
  double steps = 0.0, ceiling_steps = 0.0, ceiling_seconds = 0.0;
  for (int i = 0; i < options.iterations; ++i) {
    const IterationStats s = trainer.RunIteration();
    steps += static_cast<double>(config.num_envs) * config.steps_per_env;
    sum.seconds_total += s.seconds_total;
    sum.seconds_physics += s.seconds_physics;
    sum.seconds_policy += s.seconds_policy;
    sum.seconds_bookkeeping += s.seconds_bookkeeping;
    sum.seconds_reward += s.seconds_reward;
    sum.seconds_ppo += s.seconds_ppo;
    sum.seconds_pae += s.seconds_pae;
    sum.seconds_discriminator += s.seconds_discriminator;
    // The ceiling alternates with the iterations, so drift on a shared machine hits both alike.
    const double seconds = s.seconds_physics;
    ceiling_steps += MeasurePhysicsCeiling(trainer.vec_env(), seconds, config.seed + i) * seconds;
    ceiling_seconds += seconds;
  }
  const double rate = steps / sum.seconds_total;
  const double ceiling = ceiling_steps / ceiling_seconds;
  auto share = [&](double part) { return part / sum.seconds_total; };
  return {
      {"benchmark", "train"},
      {"machine", MachineDescription()},
      {"config", options.config},
      {"method", config.method},
      {"num_envs", config.num_envs},
      {"steps_per_env", config.steps_per_env},
      {"num_skills", config.num_skills},
      {"iterations_timed", options.iterations},
      {"seconds_per_iteration", sum.seconds_total / options.iterations},
      {"env_steps_per_s", rate},
      {"physics_ceiling_steps_per_s", ceiling},
      {"ratio", rate / ceiling},
      {"time_share",
       {{"physics", share(sum.seconds_physics)},
        {"policy_inference", share(sum.seconds_policy)},
        {"windows_and_bookkeeping", share(sum.seconds_bookkeeping)},
        {"pae_and_discriminator_rewards", share(sum.seconds_reward)},
        {"ppo_update", share(sum.seconds_ppo)},
        {"pae_update", share(sum.seconds_pae)},
        {"discriminator_update", share(sum.seconds_discriminator)}}},
  };
}

}  // namespace flsd
