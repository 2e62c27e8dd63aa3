// flsd: the learning side's command line: simulator demo, training, evaluation, export, benchmarks.

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <cstdio>

#include "bench/hw_bench.h"
#include "bench/nav_bench.h"
#include "bench/plan_bench.h"
#include "bench/policy_bench.h"
#include "bench/sim_bench.h"
#include "bench/train_bench.h"
#include "core/check.h"
#include "core/paths.h"
#include "render/skill_render.h"
#include "report/learning_curves.h"
#include "skills/learning/communicator.h"
#include "skills/learning/evaluation.h"
#include "skills/learning/export.h"
#include "skills/learning/task_trainer.h"
#include "skills/learning/tracking_eval.h"
#include "skills/learning/training_run.h"
#include "tools/flsd/report_command.h"
#include "tools/flsd/sim_demo.h"

namespace {
std::atomic<bool> g_stop{false};
void RequestStop(int) { g_stop = true; }

// In an MPI job a failing rank ends the whole job, naming itself, so that no other rank waits for
// it in a collective for ever; alone, the error is logged and the exit code returned.
int Fail(int code, const std::string& message) {
  const flsd::Communicator& comm = flsd::Communicator::World();
  if (comm.size() > 1) comm.Abort(message);
  spdlog::error("{}", message);
  return code;
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"FLSD: Fourier Latent Skill Discovery for the Unitree A1"};
  app.require_subcommand(1);

  flsd::SimDemoOptions demo;
  CLI::App* demo_cmd = app.add_subcommand("demo", "Stand the simulated A1, then drive it with random targets");
  demo_cmd->add_option("--stand-seconds", demo.stand_seconds, "Length of the standing phase")->check(CLI::Range(0.02, 3600.0));
  demo_cmd->add_option("--random-seconds", demo.random_seconds, "Length of the random-target phase")->check(CLI::Range(0.02, 3600.0));
  demo_cmd->add_option("--seed", demo.seed, "Random seed");

  flsd::TrainingRunOptions train;
  CLI::App* train_cmd = app.add_subcommand("train", "Train skills with FLSD (Algorithm 1) or the DIAYN baseline");
  train_cmd->add_option("--config", train.config_path, "Training config (configs/*.yaml)");
  train_cmd->add_option("--method", train.method, "flsd or diayn (default: the config's)")
      ->check(CLI::IsMember({"flsd", "diayn"}));
  train_cmd->add_option("--out", train.run_dir, "Run folder (config.yaml, checkpoint.pt, progress.csv)")->required();
  train_cmd->add_flag("--resume", train.resume, "Continue the run in --out from its checkpoint");
  train_cmd->add_option("--from", train.from_checkpoint,
                        "Start a new run from this checkpoint (fine-tuning with --config's settings)");
  train_cmd->add_option("--iterations", train.iterations, "Train until this many iterations in total")
      ->check(CLI::Range(1, 100000000));
  train_cmd->add_option("--seed", train.seed, "Seed of a new run (default: the config's)")->check(CLI::Range(0, 1 << 30));
  train_cmd->add_option("--threads", train.threads, "Simulation threads per process (default: the config's)")
      ->check(CLI::Range(1, 1024));

  flsd::TaskRunOptions task;
  CLI::App* task_cmd = app.add_subcommand(
      "train-selector", "Train the velocity-tracking skill selector (or, --method scratch, a policy from scratch)");
  task_cmd->add_option("--config", task.config_path, "Task training config (configs/selector_*.yaml)");
  task_cmd->add_option("--method", task.method, "selector or scratch (default: the config's)")
      ->check(CLI::IsMember({"selector", "scratch"}));
  task_cmd->add_option("--library", task.library, "Skill library the selector chooses from (default: the config's)");
  task_cmd->add_option("--out", task.run_dir, "Run folder (config.yaml, checkpoint.pt, progress.csv)")->required();
  task_cmd->add_flag("--resume", task.resume, "Continue the run in --out from its checkpoint");
  task_cmd->add_option("--iterations", task.iterations, "Train until this many iterations in total")
      ->check(CLI::Range(1, 100000000));
  task_cmd->add_option("--threads", task.threads, "Simulation threads (default: the config's)")->check(CLI::Range(1, 1024));

  std::string run_dir, library_path;
  int kept_iteration = 0;
  const char* kept_help = "Load the checkpoint the run kept at this iteration (checkpoints/ITER.pt; default: the latest)";
  flsd::EvaluationOptions eval;
  bool eval_json = false;
  CLI::App* eval_cmd = app.add_subcommand("eval", "Roll out every skill and compute the paper's metrics");
  eval_cmd->add_option("run", run_dir, "Run folder")->required();
  eval_cmd->add_flag("--randomize", eval.randomize, "Keep the training randomisation on");
  eval_cmd->add_option("--steps", eval.steps, "Steps per skill (default: the episode length)")->check(CLI::Range(1, 1000000));
  eval_cmd->add_flag("--json", eval_json, "Print the whole JSON (default: a summary)");
  eval_cmd->add_option("--iteration", kept_iteration, kept_help)->check(CLI::Range(1, 100000000));

  CLI::App* export_cmd = app.add_subcommand("export", "Write a run's skill library (safetensors)");
  export_cmd->add_option("run", run_dir, "Run folder")->required();
  export_cmd->add_option("-o,--output", library_path, "Library file to write")->required();
  export_cmd->add_option("--iteration", kept_iteration, kept_help)->check(CLI::Range(1, 100000000));

  CLI::App* export_selector_cmd =
      app.add_subcommand("export-selector", "Add a selector run's skill selector to its skill library");
  export_selector_cmd->add_option("run", run_dir, "Selector run folder (flsd train-selector)")->required();
  export_selector_cmd->add_option("-o,--output", library_path, "Library file to write")->required();

  std::string track_library = "models/a1_flsd.safetensors";
  double track_seconds = 10.0;
  CLI::App* track_cmd = app.add_subcommand(
      "track", "Track eight velocity commands with a library's learned selector and the nearest-skill selector");
  track_cmd->add_option("library", track_library, "Skill library (default: the shipped one)");
  track_cmd->add_option("--seconds", track_seconds, "Seconds per command")->check(CLI::Range(2.5, 600.0));

  flsd::RenderOptions render;
  CLI::App* render_cmd = app.add_subcommand(
      "render", "Film a skill in the simulator (.gif, .mp4, .png), or every skill as one contact sheet (.png)");
  render_cmd->add_option("--library", render.library, "Skill library (.safetensors)")->required();
  render_cmd->add_option("-o,--output", render.output, "File to write: .gif, .mp4 (needs ffmpeg) or .png")->required();
  render_cmd->add_option("--skill", render.skill, "Skill to film (from 0)");
  render_cmd->add_flag("--contact-sheet", render.contact_sheet, "One still of every skill, 4 across (.png)");
  render_cmd->add_option("--seconds", render.seconds, "Length of the rollout (a contact sheet's stills are its last frames)");
  render_cmd->add_option("--fps", render.fps, "Frames per second (1 to 50)");
  render_cmd->add_option("--width", render.width, "Frame width in pixels");
  render_cmd->add_option("--height", render.height, "Frame height in pixels");
  render_cmd->add_option("--seed", render.seed, "Seed of the initial pose");

  flsd::ReportOptions report;
  CLI::App* report_cmd =
      app.add_subcommand("report", "Compare skill runs as the paper does: an HTML page with tables and figures");
  report_cmd->add_option("runs", report.runs, "Run folders (flsd train); RUN@ITER for a checkpoint a run kept")->required();
  report_cmd->add_option("-o,--output", report.output, "Folder to write index.html, report.json and figures")->required();
  report_cmd->add_option("--steps", report.steps, "Steps per skill (default: the episode length)")
      ->check(CLI::Range(1, 1000000));

  std::vector<std::string> curve_args;
  flsd::CurvePlotOptions curves;
  CLI::App* plot_cmd = app.add_subcommand("plot", "Draw learning curves of runs as one SVG chart");
  plot_cmd->add_option("curves", curve_args, "LABEL=RUN_DIR/progress.csv ...")->required();
  plot_cmd->add_option("--x", curves.x, "Column for the x axis (default env_steps)");
  plot_cmd->add_option("--y", curves.y, "Column for the y axis (default mean_reward)");
  plot_cmd->add_option("--smooth", curves.smooth, "Moving average over this many iterations")->check(CLI::Range(1, 100000));
  plot_cmd->add_option("--title", curves.title, "Chart title");
  plot_cmd->add_option("-o,--output", curves.output, "SVG file to write")->required();

  CLI::App* bench_cmd = app.add_subcommand("bench", "Benchmarks that print JSON");
  bench_cmd->require_subcommand(1);
  flsd::SimBenchOptions sim;
  bool json = false;
  CLI::App* sim_cmd = bench_cmd->add_subcommand("sim", "VecEnv throughput against the bare mj_step ceiling");
  sim_cmd->add_option("--config", sim.config, "YAML file with an env section (default: built-in defaults)");
  sim_cmd->add_option("--envs", sim.num_envs, "Number of environments")->check(CLI::Range(1, 100000));
  sim_cmd->add_option("--threads", sim.num_threads, "Threads (0: every core)")->check(CLI::Range(0, 1024));
  sim_cmd->add_option("--seconds", sim.seconds, "Timed seconds per side")->check(CLI::Range(0.1, 3600.0));
  sim_cmd->add_option("--seed", sim.seed, "Random seed");
  sim_cmd->add_flag("--json", json, "Print one JSON object (the default output)");
  flsd::TrainBenchOptions train_bench;
  CLI::App* train_bench_cmd = bench_cmd->add_subcommand("train", "Algorithm 1 throughput against the physics ceiling");
  train_bench_cmd->add_option("--config", train_bench.config, "Training config");
  train_bench_cmd->add_option("--method", train_bench.method, "flsd or diayn")->check(CLI::IsMember({"flsd", "diayn"}));
  train_bench_cmd->add_option("--iterations", train_bench.iterations, "Timed iterations")->check(CLI::Range(1, 1000));
  train_bench_cmd->add_option("--threads", train_bench.threads, "Simulation threads per process (default: the config's)")
      ->check(CLI::Range(1, 1024));
  train_bench_cmd->add_flag("--json", json, "Print one JSON object (the default output)");
  flsd::MpiBenchOptions mpi_bench;
  CLI::App* mpi_bench_cmd =
      bench_cmd->add_subcommand("mpi", "Training throughput of N MPI ranks x 1 thread against 1 process x N threads");
  mpi_bench_cmd->add_option("--ranks", mpi_bench.ranks, "Ranks (and threads of the one process)")->check(CLI::Range(2, 1024));
  mpi_bench_cmd->add_option("--config", mpi_bench.train.config, "Training config");
  mpi_bench_cmd->add_option("--iterations", mpi_bench.train.iterations, "Timed iterations")->check(CLI::Range(1, 1000));
  mpi_bench_cmd->add_flag("--json", json, "Print one JSON object (the default output)");

  flsd::PolicyBenchOptions policy_bench;
  CLI::App* policy_bench_cmd =
      bench_cmd->add_subcommand("policy", "Serving inference (Eigen against libtorch) and control-loop jitter");
  policy_bench_cmd->add_option("--library", policy_bench.library, "Skill library");
  policy_bench_cmd->add_option("--calls", policy_bench.calls, "Timed Eigen calls")->check(CLI::Range(10, 100000000));
  policy_bench_cmd->add_option("--loop-seconds", policy_bench.loop_seconds, "Real-time control loop run")
      ->check(CLI::Range(0.1, 3600.0));
  policy_bench_cmd->add_flag("--json", json, "Print one JSON object (the default output)");

  flsd::HwBenchOptions hw_bench;
  CLI::App* hw_bench_cmd = bench_cmd->add_subcommand("hw", "The A1 UDP driver against the robot emulator on loopback");
  hw_bench_cmd->add_option("--seconds", hw_bench.seconds, "Timed seconds")->check(CLI::Range(0.5, 3600.0));
  hw_bench_cmd->add_flag("--json", json, "Print one JSON object (the default output)");

  flsd::PlanBenchOptions plan_bench;
  CLI::App* plan_bench_cmd = bench_cmd->add_subcommand("plan", "OMPL planning time and path length on the shipped maps");
  plan_bench_cmd->add_option("--trials", plan_bench.trials, "Plans per map")->check(CLI::Range(1, 10000));
  plan_bench_cmd->add_flag("--json", json, "Print one JSON object (the default output)");

  flsd::NavBenchOptions nav_bench;
  CLI::App* nav_bench_cmd =
      bench_cmd->add_subcommand("nav", "Navigation through a real skilld on every shipped map, from fresh resets");
  nav_bench_cmd->add_option("--library", nav_bench.library, "Skill library skilld serves");
  nav_bench_cmd->add_option("--goals", nav_bench.goals, "Start and goal pairs per map")->check(CLI::Range(1, 1000));
  nav_bench_cmd->add_option("--seed", nav_bench.seed, "Seed of the pairs");
  nav_bench_cmd->add_option("--domain", nav_bench.domain_id, "DDS domain of the skilld it starts")->check(CLI::Range(0, 232));
  nav_bench_cmd->add_flag("--json", json, "Print one JSON object (the default output)");

  CLI11_PARSE(app, argc, argv);
  try {
    if (*demo_cmd) return flsd::RunSimDemo(demo);
    if (*train_cmd) {
      if (!train.resume && train.config_path.empty()) throw flsd::InputError("train: --config is required for a new run");
      // Ctrl-C or a scheduler's SIGTERM ends the iteration in progress, then checkpoints.
      std::signal(SIGINT, RequestStop);
      std::signal(SIGTERM, RequestStop);
      return flsd::RunTraining(train, g_stop);
    }
    if (*task_cmd) {
      if (!task.resume && task.config_path.empty()) throw flsd::InputError("train-selector: --config is required for a new run");
      std::signal(SIGINT, RequestStop);
      std::signal(SIGTERM, RequestStop);
      return flsd::RunTaskTraining(task, g_stop);
    }
    if (*report_cmd) return flsd::RunReport(report);
    if (*render_cmd) return flsd::RunRender(render);
    if (*eval_cmd) {
      flsd::ConfigureTorchThreads(0);
      const nlohmann::json result = flsd::EvaluateRun(run_dir, eval, kept_iteration);
      if (eval_json) {
        std::printf("%s\n", result.dump(2).c_str());
      } else {
        std::printf("%s: %d of %d skills survive 500 steps; state coverage %.4f (%ld of %ld cells); "
                    "high-frequency power ratio %.4f\n",
                    run_dir.c_str(), result["skills_surviving_500_steps"].get<int>(), result["num_skills"].get<int>(),
                    result["state_coverage"]["rate"].get<double>(), result["state_coverage"]["cells_visited"].get<long>(),
                    result["state_coverage"]["cells_total"].get<long>(),
                    result["high_frequency_power_ratio"]["pooled"].get<double>());
      }
      return 0;
    }
    if (*export_cmd) {
      flsd::ConfigureTorchThreads(0);
      std::printf("%s\n", flsd::ExportRun(run_dir, library_path, kept_iteration).dump(2).c_str());
      return 0;
    }
    if (*export_selector_cmd) {
      flsd::ConfigureTorchThreads(0);
      std::printf("%s\n", flsd::ExportSelector(run_dir, library_path).dump(2).c_str());
      return 0;
    }
    if (*track_cmd) {
      const flsd::SkillLibrary library = flsd::SkillLibrary::Load(flsd::ResolveDataPath(track_library));
      std::printf("%s\n", flsd::CompareSelectors(library, track_seconds, 2.0, 1).dump(2).c_str());
      return 0;
    }
    if (*plot_cmd) {
      std::vector<flsd::CurveSpec> specs;
      for (const std::string& arg : curve_args) {
        const size_t eq = arg.find('=');
        if (eq == std::string::npos) throw flsd::InputError("plot: expected LABEL=FILE, got '" + arg + "'");
        specs.push_back({arg.substr(0, eq), arg.substr(eq + 1)});
      }
      flsd::PlotCurves(specs, curves);
      std::printf("%s\n", curves.output.c_str());
      return 0;
    }
    if (*sim_cmd) {
      std::printf("%s\n", flsd::RunSimBenchmark(sim).dump(2).c_str());
      return 0;
    }
    if (*plan_bench_cmd) {
      std::printf("%s\n", flsd::RunPlanBenchmark(plan_bench).dump(2).c_str());
      return 0;
    }
    if (*nav_bench_cmd) {
      std::printf("%s\n", flsd::RunNavBenchmark(nav_bench).dump(2).c_str());
      return 0;
    }
    if (*hw_bench_cmd) {
      std::printf("%s\n", flsd::RunHwBenchmark(hw_bench).dump(2).c_str());
      return 0;
    }
    if (*policy_bench_cmd) {
      std::printf("%s\n", flsd::RunPolicyBenchmark(policy_bench).dump(2).c_str());
      return 0;
    }
    if (*train_bench_cmd) {
      const nlohmann::json result = flsd::RunTrainBenchmark(train_bench);
      if (!result.is_null()) std::printf("%s\n", result.dump(2).c_str());  // the leader's alone
      return 0;
    }
    if (*mpi_bench_cmd) {
      std::printf("%s\n", flsd::RunMpiBenchmark(mpi_bench).dump(2).c_str());
      return 0;
    }
  } catch (const flsd::InputError& e) {
    return Fail(2, e.what());
  } catch (const std::exception& e) {
    return Fail(1, std::string("internal error: ") + e.what());
  }
  return 0;
}
