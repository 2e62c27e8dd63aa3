// flsd eval, eval-library, export, export-selector, selector-curve, compose-library, track, transitions and
// cycles.

#include <cstdio>
#include <memory>
#include <string>

#include "core/paths.h"
#include "skills/learning/evaluation/evaluation.h"
#include "skills/learning/evaluation/library_eval.h"
#include "skills/learning/evaluation/tracking_eval.h"
#include "skills/learning/evaluation/transition_eval.h"
#include "skills/learning/export/compose_library.h"
#include "skills/learning/export/export.h"
#include "skills/learning/runners/training_run.h"
#include "skills/runtime/skill_library.h"
#include "tools/flsd/subcommands.h"

namespace flsd::cli {
namespace {

struct RunArgs {
  std::string run_dir, library_path;
  int kept_iteration = 0;
  bool best = false;
  // The kept checkpoint asked for: --best's (best.json), --iteration's, or 0 for the latest.
  int Iteration() const { return best ? BestIteration(run_dir) : kept_iteration; }
};

constexpr const char* kBestHelp = "The kept checkpoint the run judged best as a library (best.json)";

int PrintJson(const nlohmann::json& result) {
  std::printf("%s\n", result.dump(2).c_str());
  return 0;
}

std::string StartsHelp() {
  return "Starts per skill, seeds SEED, SEED+1, ...: survival the worst, slip the mean (export: " +
         std::to_string(kRandomizedStarts) + " randomised; default: 1)";
}

int PrintEvaluationSummary(const std::string& name, const nlohmann::json& result) {
  const nlohmann::json& bar = result["bar"];
  const int starts = result["starts_per_skill"].get<int>();
  const std::string over = starts > 1 ? " (survival the worst of " + std::to_string(starts) + " starts, slip their mean)" : "";
  std::printf("%s: %d of %d skills survive 500 steps; state coverage %.4f (%ld of %ld cells); "
              "high-frequency power ratio %.4f\n"
              "bar %s%s: %d movers, lowest base %.3f m, fastest stance-foot slip %.3f m/s; skill per direction:",
              name.c_str(), result["skills_surviving_500_steps"].get<int>(), result["num_skills"].get<int>(),
              result["state_coverage"]["rate"].get<double>(), result["state_coverage"]["cells_visited"].get<long>(),
              result["state_coverage"]["cells_total"].get<long>(),
              result["high_frequency_power_ratio"]["pooled"].get<double>(), bar["met"].get<bool>() ? "met" : "not met",
              over.c_str(), bar["movers"].get<int>(), bar["lowest_mover_height"].get<double>(),
              bar["fastest_mover_slip"].get<double>());
  for (const auto& [direction, choice] : bar["directions"].items()) {
    std::printf(" %s %s", direction.c_str(), choice["skill"].is_null() ? "none" : choice["skill"].dump().c_str());
  }
  std::printf("\n");
  return 0;
}

}  // namespace

void AddEvaluation(CLI::App& app, Subcommands& out) {
  struct EvalArgs : RunArgs {
    EvaluationOptions options;
    int starts = 1;
    bool json = false;
  };
  auto eval = std::make_shared<EvalArgs>();
  CLI::App* eval_cmd = app.add_subcommand("eval", "Roll out every skill and compute the paper's metrics");
  eval_cmd->add_option("run", eval->run_dir, "Run folder")->required();
  eval_cmd->add_flag("--randomize", eval->options.randomize, "Keep the training randomisation on");
  eval_cmd->add_flag("--standing-start", eval->options.standing_start,
                    "With --randomize: start each skill at rest in the default pose, as skilld does, not tossed");
  eval_cmd->add_option("--steps", eval->options.steps, "Steps per skill (default: the episode length)")
      ->check(CLI::Range(1, 1000000));
  eval_cmd->add_option("--seed", eval->options.seed, "Seed of the starts and the randomisation (default: 1)");
  eval_cmd->add_option("--starts", eval->starts, StartsHelp())->check(CLI::Range(1, 1000));
  eval_cmd->add_flag("--json", eval->json, "Print the whole JSON (default: a summary)");
  CLI::Option* eval_iteration =
      eval_cmd->add_option("--iteration", eval->kept_iteration, kKeptIterationHelp)->check(CLI::Range(1, 100000000));
  eval_cmd->add_flag("--best", eval->best, kBestHelp)->excludes(eval_iteration);
  out.push_back({eval_cmd, [eval] {
                   ConfigureLearningProcess(0);
                   const nlohmann::json result = EvaluateRun(eval->run_dir, eval->options, eval->Iteration(), eval->starts);
                   return eval->json ? PrintJson(result) : PrintEvaluationSummary(eval->run_dir, result);
                 }});

  struct EvalLibraryArgs {
    std::string library = "models/a1_flsd.safetensors";
    EvaluationOptions options;
    int starts = 1;
    bool json = false;
  };
  auto eval_library = std::make_shared<EvalLibraryArgs>();
  CLI::App* eval_library_cmd = app.add_subcommand(
      "eval-library", "Roll out every skill of a library as skilld runs it, compute the paper's metrics and judge the bar");
  eval_library_cmd->add_option("library", eval_library->library, "Skill library (default: the shipped one)");
  eval_library_cmd->add_flag("--randomize", eval_library->options.randomize, "Keep the training randomisation on");
  eval_library_cmd->add_flag("--standing-start", eval_library->options.standing_start,
                    "With --randomize: start each skill at rest in the default pose, as skilld does, not tossed");
  eval_library_cmd->add_option("--steps", eval_library->options.steps, "Steps per skill (default: the episode length)")
      ->check(CLI::Range(1, 1000000));
  eval_library_cmd->add_option("--seed", eval_library->options.seed, "Seed of the start and the randomisation (default: 1)");
  eval_library_cmd->add_option("--starts", eval_library->starts, StartsHelp())->check(CLI::Range(1, 1000));
  eval_library_cmd->add_flag("--json", eval_library->json, "Print the whole JSON (default: a summary)");
  out.push_back({eval_library_cmd, [eval_library] {
                   const SkillLibrary library = SkillLibrary::Load(ResolveDataPath(eval_library->library));
                   nlohmann::json result = EvaluationJson(
                       EvaluateOverStarts(eval_library->options, eval_library->starts,
                                          [&](const EvaluationOptions& o) { return EvaluateLibrary(library, o); }));
                   result["library"] = eval_library->library;
                   result["standing_start"] = eval_library->options.RandomizedFromStand();
                   return eval_library->json ? PrintJson(result) : PrintEvaluationSummary(eval_library->library, result);
                 }});

  auto export_args = std::make_shared<RunArgs>();
  CLI::App* export_cmd = app.add_subcommand("export", "Write a run's skill library (safetensors)");
  export_cmd->add_option("run", export_args->run_dir, "Run folder")->required();
  export_cmd->add_option("-o,--output", export_args->library_path, "Library file to write")->required();
  CLI::Option* export_iteration = export_cmd->add_option("--iteration", export_args->kept_iteration, kKeptIterationHelp)
                                       ->check(CLI::Range(1, 100000000));
  export_cmd->add_flag("--best", export_args->best, kBestHelp)->excludes(export_iteration);
  out.push_back({export_cmd, [export_args] {
                   ConfigureLearningProcess(0);
                   return PrintJson(ExportRun(export_args->run_dir, export_args->library_path, export_args->Iteration()));
                 }});

  auto selector = std::make_shared<RunArgs>();
  CLI::App* export_selector_cmd =
      app.add_subcommand("export-selector", "Add a selector run's skill selector to its skill library");
  export_selector_cmd->add_option("run", selector->run_dir, "Selector run folder (flsd train-selector)")->required();
  export_selector_cmd->add_option("-o,--output", selector->library_path, "Library file to write")->required();
  export_selector_cmd->add_option("--iteration", selector->kept_iteration, kKeptIterationHelp)
      ->check(CLI::Range(1, 100000000));
  out.push_back({export_selector_cmd, [selector] {
                   ConfigureLearningProcess(0);
                   return PrintJson(ExportSelector(selector->run_dir, selector->library_path, selector->kept_iteration));
                 }});

  struct CurveArgs {
    std::string run_dir, cases_library;
  };
  auto curve = std::make_shared<CurveArgs>();
  CLI::App* curve_cmd = app.add_subcommand(
      "selector-curve", "Track the fixed evaluation set with each kept checkpoint of a selector run, and the latest");
  curve_cmd->add_option("run", curve->run_dir, "Selector run folder (flsd train-selector)")->required();
  curve_cmd->add_option("--cases-from", curve->cases_library,
                        "The library whose evaluation set is tracked (default: the run's own)");
  out.push_back({curve_cmd, [curve] {
                   ConfigureLearningProcess(0);
                   return PrintJson(SelectorCurve(
                       curve->run_dir, curve->cases_library.empty() ? "" : ResolveDataPath(curve->cases_library)));
                 }});

  struct ComposeArgs {
    std::vector<std::string> parts;
    std::string output;
  };
  auto compose = std::make_shared<ComposeArgs>();
  CLI::App* compose_cmd = app.add_subcommand(
      "compose-library", "Join skills of several libraries into one; each skill keeps the policy that trained it");
  compose_cmd->add_option("libraries", compose->parts, "LIBRARY (all its skills) or LIBRARY:K,K,... (those skills), in order")
      ->required();
  compose_cmd->add_option("-o,--output", compose->output, "Library file to write")->required();
  out.push_back({compose_cmd, [compose] {
                   std::vector<LibraryPart> parts;
                   for (const std::string& text : compose->parts) parts.push_back(ParseLibraryPart(text));
                   return PrintJson(ComposeLibraries(parts, compose->output));
                 }});

  struct TrackArgs {
    std::string library = "models/a1_flsd.safetensors";
    double seconds = 10.0;
    std::string cases = "evaluation";
  };
  auto track = std::make_shared<TrackArgs>();
  CLI::App* track_cmd = app.add_subcommand(
      "track", "Track velocity commands with a library's learned selector and the nearest-skill and time-sharing selectors");
  track_cmd->add_option("library", track->library, "Skill library (default: the shipped one)");
  track_cmd->add_option("--seconds", track->seconds, "Seconds per command")->check(CLI::Range(2.5, 600.0));
  track_cmd
      ->add_option("--cases", track->cases,
                   "standard: the eight commands; evaluation: those and 32 drawn once over the library's envelope")
      ->check(CLI::IsMember({"standard", "evaluation"}));
  out.push_back({track_cmd, [track] {
                   const SkillLibrary library = SkillLibrary::Load(ResolveDataPath(track->library));
                   const std::vector<TrackingCase> cases =
                       track->cases == "standard" ? StandardTrackingCases() : EvaluationTrackingCases(library);
                   return PrintJson(CompareSelectors(library, cases, track->seconds, 2.0, kTrackingEnvSeed));
                 }});

  struct TransitionArgs {
    std::string library = "models/a1_flsd.safetensors";
    std::vector<double> first{2.0};
    double seconds = 4.0;
    int handovers = 5;
    bool record = false;
  };
  auto transitions = std::make_shared<TransitionArgs>();
  CLI::App* transitions_cmd = app.add_subcommand(
      "transitions", "Switch between every ordered pair of a library's dependable skills, and count the falls");
  transitions_cmd->add_option("library", transitions->library, "Skill library (default: the shipped one)");
  transitions_cmd
      ->add_option("--first", transitions->first,
                   "Seconds the first skill runs from a stand; several: each is run, and a switch that fell in any "
                   "is recorded")
      ->check(CLI::Range(0.5, 60.0));
  transitions_cmd->add_option("--seconds", transitions->seconds, "Seconds the second skill runs")
      ->check(CLI::Range(1.5, 60.0));
  transitions_cmd->add_option("--handovers", transitions->handovers,
                              "Switches per pair, the first skill running 0.1 s longer each time")
      ->check(CLI::Range(1, 50));
  transitions_cmd->add_flag("--record", transitions->record,
                            "Record the switches that fell in the library, so that skilld's selectors never make them");
  out.push_back({transitions_cmd, [transitions] {
                   const std::string path = ResolveDataPath(transitions->library);
                   const SkillLibrary library = SkillLibrary::Load(path);
                   std::vector<TransitionEvaluation> evaluations;
                   nlohmann::json out = nlohmann::json::array();
                   for (double first : transitions->first) {
                     evaluations.push_back(EvaluateTransitions(library, TrainingEnvOf(library), first,
                                                               transitions->seconds, 1.0, 1, transitions->handovers));
                     out.push_back(TransitionJson(evaluations.back()));
                   }
                   if (transitions->record) RecordTransitions(path, evaluations);
                   return PrintJson(out.size() == 1 ? out[0] : out);
                 }});

  struct CycleArgs {
    std::string library = "models/a1_flsd.safetensors";
    int per_axis = 15;
    int periods = 8;
    bool record = false;
  };
  auto cycles = std::make_shared<CycleArgs>();
  CLI::App* cycles_cmd = app.add_subcommand(
      "cycles", "Play the time-sharing selector's cycles for several periods from a stand, and count the falls");
  cycles_cmd->add_option("library", cycles->library, "Skill library (default: the shipped one)");
  cycles_cmd
      ->add_option("--per-axis", cycles->per_axis,
                   "Commands per axis of the grid over the selector's command range whose cycles are played")
      ->check(CLI::Range(1, 30));
  cycles_cmd->add_option("--periods", cycles->periods, "Periods each cycle is played")->check(CLI::Range(1, 20));
  cycles_cmd->add_flag("--record", cycles->record,
                       "Record the cycles that fell in the library, so that skilld's selectors never play them (after "
                       "flsd transitions --record)");
  out.push_back({cycles_cmd, [cycles] {
                   const std::string path = ResolveDataPath(cycles->library);
                   const SkillLibrary library = SkillLibrary::Load(path);
                   const CycleEvaluation evaluation =
                       EvaluateCycles(library, TrainingEnvOf(library), cycles->per_axis, cycles->periods, 1);
                   if (cycles->record) RecordCycles(path, evaluation);
                   return PrintJson(CycleJson(evaluation));
                 }});
}

}  // namespace flsd::cli
