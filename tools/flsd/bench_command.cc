// flsd bench: sim, train, mpi, policy, hw, plan, nav, vel, soak. Each prints one JSON object.

#include <cstdio>
#include <memory>

#include "bench/hw_bench.h"
#include "bench/nav_bench.h"
#include "bench/plan_bench.h"
#include "bench/policy_bench.h"
#include "bench/sim_bench.h"
#include "bench/soak_bench.h"
#include "bench/train_bench.h"
#include "bench/vel_bench.h"
#include "tools/flsd/subcommands.h"

namespace flsd::cli {
namespace {

// A benchmark subcommand of `bench` whose options `Options` are bound by `bind` and whose
// `run(options)` gives the JSON to print (null: this rank prints nothing).
template <class Options, class Bind, class Runner>
void AddBenchmark(CLI::App& bench, Subcommands& out, const char* name, const char* description, Bind bind,
                  Runner run) {
  auto options = std::make_shared<Options>();
  CLI::App* cmd = bench.add_subcommand(name, description);
  bind(*cmd, *options);
  // JSON is the only output; the flag stays for scripts that pass it.
  cmd->add_flag("--json", "Print one JSON object (the default output)");
  out.push_back({cmd, [options, run] {
                   const nlohmann::json result = run(*options);
                   if (!result.is_null()) std::printf("%s\n", result.dump(2).c_str());
                   // A benchmark that also checks correctness (soak) says whether it held.
                   return result.is_object() && !result.value("passed", true) ? 1 : 0;
                 }});
}

}  // namespace

void AddBenchmarks(CLI::App& app, Subcommands& out) {
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks that print JSON");
  bench->require_subcommand(1);
  AddBenchmark<SimBenchOptions>(
      *bench, out, "sim", "VecEnv throughput against the bare mj_step ceiling",
      [](CLI::App& cmd, SimBenchOptions& o) {
        cmd.add_option("--config", o.config, "YAML file with an env section (default: built-in defaults)");
        cmd.add_option("--envs", o.num_envs, "Number of environments")->check(CLI::Range(1, 100000));
        cmd.add_option("--threads", o.num_threads, "Threads (0: every core)")->check(CLI::Range(0, 1024));
        cmd.add_option("--seconds", o.seconds, "Timed seconds per side")->check(CLI::Range(0.1, 3600.0));
        cmd.add_option("--seed", o.seed, "Random seed");
      },
      RunSimBenchmark);
  AddBenchmark<TrainBenchOptions>(
      *bench, out, "train", "Algorithm 1 throughput against the physics ceiling",
      [](CLI::App& cmd, TrainBenchOptions& o) {
        cmd.add_option("--config", o.config, "Training config");
        cmd.add_option("--method", o.method, "flsd or diayn")->check(CLI::IsMember({"flsd", "diayn"}));
        cmd.add_option("--iterations", o.iterations, "Timed iterations")->check(CLI::Range(1, 1000));
        cmd.add_option("--threads", o.threads, "Simulation threads per process (default: the config's)")
            ->check(CLI::Range(1, 1024));
      },
      RunTrainBenchmark);  // the leader's result alone; other ranks return null
  AddBenchmark<MpiBenchOptions>(
      *bench, out, "mpi", "Training throughput of N MPI ranks x 1 thread against 1 process x N threads",
      [](CLI::App& cmd, MpiBenchOptions& o) {
        cmd.add_option("--ranks", o.ranks, "Ranks (and threads of the one process)")->check(CLI::Range(2, 1024));
        cmd.add_option("--config", o.train.config, "Training config");
        cmd.add_option("--iterations", o.train.iterations, "Timed iterations")->check(CLI::Range(1, 1000));
      },
      RunMpiBenchmark);
  AddBenchmark<PolicyBenchOptions>(
      *bench, out, "policy", "Serving inference (Eigen against libtorch) and control-loop jitter",
      [](CLI::App& cmd, PolicyBenchOptions& o) {
        cmd.add_option("--library", o.library, "Skill library");
        cmd.add_option("--calls", o.calls, "Timed Eigen calls")->check(CLI::Range(10, 100000000));
        cmd.add_option("--loop-seconds", o.loop_seconds, "Real-time control loop run")->check(CLI::Range(0.1, 3600.0));
      },
      RunPolicyBenchmark);
  AddBenchmark<HwBenchOptions>(
      *bench, out, "hw", "The A1 UDP driver against the robot emulator on loopback",
      [](CLI::App& cmd, HwBenchOptions& o) {
        cmd.add_option("--seconds", o.seconds, "Timed seconds")->check(CLI::Range(0.5, 3600.0));
      },
      RunHwBenchmark);
  AddBenchmark<PlanBenchOptions>(
      *bench, out, "plan", "OMPL planning time and path length on the shipped maps",
      [](CLI::App& cmd, PlanBenchOptions& o) {
        cmd.add_option("--trials", o.trials, "Plans per map")->check(CLI::Range(1, 10000));
      },
      RunPlanBenchmark);
  AddBenchmark<NavBenchOptions>(
      *bench, out, "nav", "Navigation through a real skilld on every shipped map, from fresh resets",
      [](CLI::App& cmd, NavBenchOptions& o) {
        cmd.add_option("--library", o.library, "Skill library skilld serves");
        cmd.add_option("--server-config", o.server_config, "skilld's config (default: skilld's, configs/server.yaml)");
        cmd.add_option("--goals", o.goals, "Start and goal pairs per map")->check(CLI::Range(1, 1000));
        cmd.add_option("--seed", o.seed, "Seed of the pairs");
        cmd.add_option("--domain", o.domain_id, "DDS domain of the skilld it starts")->check(CLI::Range(0, 232));
      },
      RunNavBenchmark);
  AddBenchmark<VelBenchOptions>(
      *bench, out, "vel", "Tracking commands through a real skilld, from fresh resets",
      [](CLI::App& cmd, VelBenchOptions& o) {
        cmd.add_option("--library", o.library, "Skill library skilld serves");
        cmd.add_option("--server-config", o.server_config, "skilld's config (default: skilld's, configs/server.yaml)");
        cmd.add_option("--seconds", o.seconds, "Seconds each command is held")->check(CLI::Range(0.5, 600.0));
        cmd.add_option("--settle", o.settle_seconds, "Seconds before the velocity is measured")
            ->check(CLI::Range(0.0, 600.0));
        cmd.add_option("--cases", o.cases, "standard: the eight commands; evaluation: those and 32 drawn once")
            ->check(CLI::IsMember({"standard", "evaluation"}));
        cmd.add_option("--domain", o.domain_id, "DDS domain of the skilld it starts")->check(CLI::Range(0, 232));
      },
      RunVelBenchmark);
  AddBenchmark<SoakBenchOptions>(
      *bench, out, "soak", "A real skilld under random valid and invalid calls of several clients, every reply checked",
      [](CLI::App& cmd, SoakBenchOptions& o) {
        cmd.add_option("--minutes", o.minutes, "How long the clients call")->check(CLI::Range(0.1, 1440.0));
        cmd.add_option("--clients", o.clients, "Client processes")->check(CLI::Range(1, 64));
        cmd.add_option("--backend", o.backend, "sim, or hw: the robot emulator with injected faults")
            ->check(CLI::IsMember({"sim", "hw"}));
        cmd.add_flag("--security", o.security, "DDS Security, with a PKI of the run's own");
        cmd.add_flag("--beside-training", o.beside_training, "flsd train (configs/smoke.yaml, 1 thread) all along");
        cmd.add_flag("!--no-heavy-maps", o.heavy_maps, "Leave out the heaviest maps");
        cmd.add_option("--rate", o.rate_hz, "Requests per second of each client")->check(CLI::Range(1.0, 500.0));
        cmd.add_option("--library", o.library, "Skill library skilld serves");
        cmd.add_option("--seed", o.seed, "Seed of the clients' requests");
        cmd.add_option("--domain", o.domain_id, "DDS domain of the skilld it starts")->check(CLI::Range(0, 232));
      },
      RunSoakBenchmark);
}

}  // namespace flsd::cli
