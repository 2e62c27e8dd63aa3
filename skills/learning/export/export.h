#pragma once
// `flsd export`: a run's policy as a self-describing skill library (docs/training.md, "Export"):
// one safetensors file whose tensors are the policy's layers and its observation
// normaliser, and whose metadata says everything needed to run it safely.

#include <nlohmann/json.hpp>

#include <string>

#include "skills/learning/evaluation/evaluation.h"
#include "skills/learning/tasks/skill_discovery_task.h"

namespace flsd {


struct ExportProvenance {
  std::string run;          // run folder
  std::string commits;      // the commits that trained it (run_dir/commits)
  std::string export_commit;
};

// The library's metadata: format, robot, joint order, observation layout and scales, action
// scale, default pose, gains, rates, limits, network shapes, training config and provenance,
// evaluation metrics (without and with the training randomisation) and one descriptor per skill.
nlohmann::json SkillLibraryMetadata(const TrainConfig& config, const TrainedPolicy& policy, const Evaluation& evaluation,
                                    const Evaluation& randomized, const ExportProvenance& provenance);

// Writes the library (atomically) to `path`.
void WriteSkillLibrary(const std::string& path, const TrainConfig& config, const TrainedPolicy& policy,
                       const Evaluation& evaluation, const Evaluation& randomized, const ExportProvenance& provenance);

// Loads a run (its latest checkpoint, or the one kept at `iteration`), evaluates it without
// randomisation and with it (kRandomizedStarts starts), and writes its library to `path`.
nlohmann::json ExportRun(const std::string& run_dir, const std::string& path, int iteration = 0);

// Adds a selector run's (flsd train-selector) selector, from its latest checkpoint or the one
// kept at `iteration`, to the library it was trained over and writes the result to `path` (which
// may be that library itself). Refuses if the library changed since training. The selector's
// tracking evaluation on the fixed evaluation set (tracking_eval.h) goes into its metadata.
nlohmann::json ExportSelector(const std::string& run_dir, const std::string& path, int iteration = 0);

// A velocity run's evaluation over training (Fig. 8's second axis): each kept checkpoint and the
// latest, a selector's exported, tracked on the fixed evaluation set of `cases_library` (empty: of
// the library the run chose from; selectors over different libraries, and a scratch run, which
// needs it named, are compared on one set). Rows
// of iteration, env_steps, the RMS errors, falls and switches per second; also written to
// run_dir/selector_curve.json.
nlohmann::json SelectorCurve(const std::string& run_dir, const std::string& cases_library = "");

}  // namespace flsd
