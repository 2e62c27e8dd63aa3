#include "tools/flsd/report_command.h"

#include <memory>

#include <spdlog/spdlog.h>

#include <filesystem>
#include <set>

#include "core/check.h"
#include "flsd_commit.h"
#include "report/skill_report.h"
#include "skills/learning/evaluation/evaluation.h"
#include "skills/learning/export/export.h"
#include "skills/learning/runners/run_folder.h"
#include "skills/learning/tasks/skill_discovery_task.h"
#include "tools/flsd/subcommands.h"

namespace flsd {
namespace {

namespace fs = std::filesystem;

// `spec` is a run folder, or FOLDER@ITER for the checkpoint it kept at iteration ITER.
ReportRun EvaluateForReport(const std::string& spec, int steps) {
  const std::size_t at = spec.rfind('@');
  int iteration = 0;
  if (at != std::string::npos) {
    const std::optional<int> parsed = ParseIteration(spec.substr(at + 1));
    if (!parsed) throw InputError("report: '" + spec + "': expected RUN or RUN@ITERATION, with a whole number after '@'");
    iteration = *parsed;
  }
  const std::string run_dir = spec.substr(0, at);
  const fs::path dir = fs::path(run_dir).lexically_normal();
  const TrainConfig config = LoadTrainConfig((dir / "config.yaml").string());
  const TrainedPolicy trained = LoadTrainedPolicy(config, RunCheckpoint(run_dir, iteration));
  ReportRun run;
  run.label = (dir.has_filename() ? dir.filename() : dir.parent_path().filename()).string();
  if (iteration > 0) run.label += "_" + std::to_string(iteration);
  run.method = config.method;
  run.seed = config.seed;
  run.iteration = trained.iteration;
  run.env_steps = trained.env_steps;
  if (fs::exists(dir / "progress.csv")) run.progress_csv = (dir / "progress.csv").string();
  EvaluationOptions options;
  options.steps = steps;
  run.nominal = EvaluateSkills(config, trained.policy, trained.normalizer, options);
  options.randomize = true;
  run.randomized = EvaluateOverStarts(options, kRandomizedStarts, [&](const EvaluationOptions& o) {
    return EvaluateSkills(config, trained.policy, trained.normalizer, o);
  });
  spdlog::info("{}: {} at iteration {}, {} of {} skills survive 500 steps ({} in every randomised start), coverage {} cells",
               run.label, run.method, run.iteration, run.nominal.survivors, run.nominal.skills.size(),
               run.randomized.survivors, run.nominal.coverage.cells_visited);
  return run;
}

}  // namespace

int RunReport(const ReportOptions& options) {
  std::vector<ReportRun> runs;
  std::set<std::string> labels;
  for (const std::string& dir : options.runs) {
    runs.push_back(EvaluateForReport(dir, options.steps));
    // Figures are named after the run folders.
    if (!labels.insert(runs.back().label).second) {
      throw InputError("report: two runs are named '" + runs.back().label + "'; give runs distinct folder names");
    }
  }
  WriteSkillReport(runs, options.output, FLSD_GIT_COMMIT);
  spdlog::info("wrote {}/index.html", options.output);
  return 0;
}

namespace cli {

void AddReport(CLI::App& app, Subcommands& out) {
  auto report = std::make_shared<ReportOptions>();
  CLI::App* cmd =
      app.add_subcommand("report", "Compare skill runs as the paper does: an HTML page with tables and figures");
  cmd->add_option("runs", report->runs, "Run folders (flsd train); RUN@ITER for a checkpoint a run kept")->required();
  cmd->add_option("-o,--output", report->output, "Folder to write index.html, report.json and figures")->required();
  cmd->add_option("--steps", report->steps, "Steps per skill (default: the episode length)")->check(CLI::Range(1, 1000000));
  out.push_back({cmd, [report] { return RunReport(*report); }});
}

}  // namespace cli
}  // namespace flsd
