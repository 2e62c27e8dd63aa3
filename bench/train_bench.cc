#include "bench/train_bench.h"

#include <unistd.h>

#include <array>
#include <cstdio>

#include "bench/learning_arithmetic.h"
#include "bench/machine.h"
#include "core/check.h"
#include "bench/sim_bench.h"
#include "core/paths.h"
#include "skills/learning/runners/on_policy_runner.h"
#include "skills/learning/runners/training_run.h"
#include "skills/learning/tasks/skill_discovery_task.h"

namespace flsd {

nlohmann::json RunTrainBenchmark(const TrainBenchOptions& options) {
  TrainConfig config = LoadTrainConfig(ResolveDataPath(options.config));
  if (!options.method.empty()) config.method = options.method;
  if (options.threads > 0) config.num_threads = options.threads;
  ConfigureLearningProcess(config.num_threads);
  const Communicator& comm = Communicator::World();
  SkillDiscoveryTask task(config, comm);
  OnPolicyRunner runner(task, config.ppo, config.seed, comm);
  runner.RunIteration();  // warm-up: first-touch allocations in libtorch and the rollout

  RunnerStats sum;
  SkillDiscoveryStats task_sum;
  Communicator::Tally collectives;
  LearningArithmetic gflop;
  double steps = 0.0, ceiling_steps = 0.0, ceiling_seconds = 0.0;
  for (int i = 0; i < options.iterations; ++i) {
    const RunnerStats s = runner.RunIteration();
    const SkillDiscoveryStats& t = task.stats();
    steps += static_cast<double>(config.num_envs) * config.steps_per_env;
    collectives.seconds += s.collectives.seconds;
    collectives.calls += s.collectives.calls;
    collectives.bytes += s.collectives.bytes;
    sum.seconds_total += s.seconds_total;
    sum.seconds_policy += s.seconds_policy;
    sum.seconds_finish += s.seconds_finish;
    sum.seconds_ppo += s.seconds_ppo;
    task_sum.seconds_physics += t.seconds_physics;
    task_sum.seconds_bookkeeping += t.seconds_bookkeeping;
    task_sum.seconds_pae += t.seconds_pae;
    task_sum.seconds_discriminator += t.seconds_discriminator;
    const LearningArithmetic a = ArithmeticOfLastIteration(task);
    gflop.policy_inference += a.policy_inference;
    gflop.rewards += a.rewards;
    gflop.ppo_update += a.ppo_update;
    gflop.pae_update += a.pae_update;
    gflop.discriminator_update += a.discriminator_update;
    // The ceiling alternates with the iterations, so drift on a shared machine hits both alike.
    const double seconds = t.seconds_physics;
    ceiling_steps += MeasurePhysicsCeiling(task.vec_env(), seconds, config.seed + i) * seconds;
    ceiling_seconds += seconds;
  }
  // The GEMM rate of the same BLAS and threads, measured as the last thing in the same run.
  const double sgemm = MeasureSgemmGflops(1024, 1.0);
  const double rate = steps / sum.seconds_total;
  // Every rank measured the ceiling of its own share at once: the job's is their sum.
  const double ceiling = comm.Sum(ceiling_steps / ceiling_seconds);
  const double collective_seconds = comm.Sum(collectives.seconds) / comm.size();  // per rank, mean
  if (!comm.leader()) return nullptr;
  auto share = [&](double part) { return part / sum.seconds_total; };
  // The most this run's algorithm could reach on this machine: physics and bookkeeping as
  // measured, every learning phase's arithmetic at the full sgemm rate (no per-call overhead).
  const double learning_gflop =
      gflop.policy_inference + gflop.rewards + gflop.ppo_update + gflop.pae_update + gflop.discriminator_update;
  const double bound_seconds =
      task_sum.seconds_physics + task_sum.seconds_bookkeeping + learning_gflop / sgemm;
  // A phase that did not run (no PAE for DIAYN, say) has no rate: 0, not 0 / 0.
  auto arithmetic = [&](double seconds, double giga) {
    const double rate = seconds > 0.0 ? giga / seconds : 0.0;
    return nlohmann::json{{"seconds_per_iteration", seconds / options.iterations},
                          {"gflop_per_iteration", giga / options.iterations},
                          {"gflops", rate},
                          {"of_sgemm", rate / sgemm}};
  };
  return {
      {"benchmark", "train"},
      {"machine", MachineDescription()},
      {"config", options.config},
      {"method", config.method},
      {"ranks", comm.size()},
      {"threads_per_rank", config.num_threads},
      {"num_envs", config.num_envs},
      {"steps_per_env", config.steps_per_env},
      {"num_skills", config.num_skills},
      {"iterations_timed", options.iterations},
      {"seconds_per_iteration", sum.seconds_total / options.iterations},
      {"env_steps_per_s", rate},
      {"physics_ceiling_steps_per_s", ceiling},
      {"ratio", rate / ceiling},
      {"ratio_if_learning_at_sgemm", steps / bound_seconds / ceiling},
      {"collectives_per_iteration",
       {{"seconds", collective_seconds / options.iterations},
        {"calls", collectives.calls / options.iterations},
        {"bytes_per_rank", collectives.bytes / options.iterations}}},
      {"rollout_seconds_per_iteration",
       (task_sum.seconds_physics + sum.seconds_policy + task_sum.seconds_bookkeeping) / options.iterations},
      {"time_share",
       {{"physics", share(task_sum.seconds_physics)},
        {"policy_inference", share(sum.seconds_policy)},
        {"windows_and_bookkeeping", share(task_sum.seconds_bookkeeping)},
        {"pae_and_discriminator_rewards", share(sum.seconds_finish)},
        {"ppo_update", share(sum.seconds_ppo)},
        {"pae_update", share(task_sum.seconds_pae)},
        {"discriminator_update", share(task_sum.seconds_discriminator)}}},
      {"sgemm_gflops", sgemm},
      {"learning_arithmetic",
       {{"policy_inference", arithmetic(sum.seconds_policy, gflop.policy_inference)},
        {"rewards", arithmetic(sum.seconds_finish, gflop.rewards)},
        {"ppo_update", arithmetic(sum.seconds_ppo, gflop.ppo_update)},
        {"pae_update", arithmetic(task_sum.seconds_pae, gflop.pae_update)},
        {"discriminator_update", arithmetic(task_sum.seconds_discriminator, gflop.discriminator_update)}}},
  };
}

namespace {

// Runs `command` and parses the JSON object it prints (from its first line that opens one).
nlohmann::json RunJsonCommand(const std::string& command) {
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) throw InputError("bench mpi: cannot run: " + command);
  std::string output;
  std::array<char, 4096> buffer;
  while (size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), n);
  const int status = pclose(pipe);
  size_t json = output.rfind('{', 0) == 0 ? 0 : output.find("\n{");
  if (json != 0 && json != std::string::npos) ++json;
  if (status != 0 || json == std::string::npos) {
    throw InputError("bench mpi: `" + command + "` failed (status " + std::to_string(status) + "):\n" + output);
  }
  return nlohmann::json::parse(output.substr(json));
}

}  // namespace

nlohmann::json RunMpiBenchmark(const MpiBenchOptions& options) {
  const std::string self = ProgramPath();
  std::string train = " bench train --json --config " + options.train.config + " --iterations " +
                      std::to_string(options.train.iterations);
  if (!options.train.method.empty()) train += " --method " + options.train.method;
  // Open MPI refuses root unless told; --oversubscribe lets a test machine run more ranks than cores.
  const std::string mpirun = std::string("mpirun -np ") + std::to_string(options.ranks) + " --oversubscribe" +
                             (geteuid() == 0 ? " --allow-run-as-root" : "");
  const nlohmann::json threads = RunJsonCommand(self + train + " --threads " + std::to_string(options.ranks));
  const nlohmann::json ranks = RunJsonCommand(mpirun + " " + self + train + " --threads 1");
  return {{"benchmark", "train_mpi"},
          {"machine", MachineDescription()},
          {"ranks_x_1_thread", ranks},
          {"1_rank_x_threads", threads},
          {"ratio", ranks["env_steps_per_s"].get<double>() / threads["env_steps_per_s"].get<double>()},
          {"target", 0.9}};
}

}  // namespace flsd
