#include "skills/learning/export/export.h"

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "core/atomic_file.h"
#include "core/check.h"
#include "flsd_commit.h"
#include "robot/observation.h"
#include "skills/learning/runners/run_folder.h"
#include "skills/learning/tasks/velocity_tracking_task.h"
#include "skills/learning/evaluation/tracking_eval.h"
#include "skills/runtime/skill_library.h"
#include "skills/runtime/library_format.h"
#include "skills/runtime/safetensors.h"
#include "skills/runtime/skill_library.h"

namespace flsd {
namespace {

FloatTensor ToFloatTensor(const torch::Tensor& t) {
  const torch::Tensor c = t.detach().to(torch::kFloat32).contiguous();
  FloatTensor out;
  out.shape.assign(c.sizes().begin(), c.sizes().end());
  out.values.assign(c.data_ptr<float>(), c.data_ptr<float>() + c.numel());
  return out;
}

// The Linear layers of `mlp` as `layer_prefix`layer<l>.{weight,bias}, and the normaliser as
// `normalizer_prefix`{mean,std}: the layout SkillLibrary reads (skills/runtime/skill_library.cc).
void AddNetwork(SafeTensors& file, const torch::nn::Sequential& mlp, const RunningNormalizer& normalizer,
                const std::string& layer_prefix, const std::string& normalizer_prefix) {
  int layer = 0;
  for (const auto& module : mlp->children()) {
    if (const auto* linear = module->as<torch::nn::Linear>()) {
      const std::string name = layer_prefix + "layer" + std::to_string(layer++);
      file.tensors[name + ".weight"] = ToFloatTensor(linear->weight);
      file.tensors[name + ".bias"] = ToFloatTensor(linear->bias);
    }
  }
  file.tensors[normalizer_prefix + "mean"] = ToFloatTensor(normalizer->mean());
  file.tensors[normalizer_prefix + "std"] = ToFloatTensor(normalizer->Std());
}

// The run's commits file; a run without one says so rather than leaving provenance blank.
std::string ReadCommits(const std::string& path) {
  std::ifstream in(path);
  if (!in) return "unknown (the run has no commits file)";
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

nlohmann::json SkillLibraryMetadata(const TrainConfig& config, const TrainedPolicy& policy, const Evaluation& evaluation,
                                    const Evaluation& randomized, const ExportProvenance& provenance) {
  nlohmann::json metadata;
  auto write = [&](const std::string& pointer, const auto& value) {
    metadata[nlohmann::json::json_pointer(pointer)] = value;
  };
  VisitLibraryFacts(write);
  LibraryValues values{config.num_skills, config.env.action_filter_hz, config.env.action_filter_order};
  values.Visit([&](const char* pointer, const auto& field, bool, double, double) { write(pointer, field); });
  // One policy: the run's.
  VisitPolicyFacts(write, 0, config.num_skills);
  nlohmann::json& run_policy = metadata["policies"][0];
  run_policy["hidden"] = config.policy.actor_hidden;
  run_policy["layers"] = config.policy.actor_hidden.size() + 1;
  run_policy["normalizer_eps"] = RunningNormalizerImpl::kEps;
  run_policy["training"] = {{"method", config.method},
                            {"iteration", policy.iteration},
                            {"env_steps", policy.env_steps},
                            {"config", ToYamlString(config)},
                            {"run", provenance.run},
                            {"commits", provenance.commits},
                            {"export_commit", provenance.export_commit}};
  nlohmann::json evaluation_json = EvaluationJson(evaluation);
  evaluation_json.erase("skills");  // per skill, the descriptors below
  run_policy["evaluation"] = evaluation_json;
  run_policy["randomized_evaluation"] = EvaluationJson(randomized);
  nlohmann::json skills = nlohmann::json::array();
  const mirror::SkillPairing pairing = SkillPairingOf(config.num_skills, config.symmetry);
  for (const SkillSummary& s : evaluation.skills) {
    SkillDescriptor d = DescribeSkill(s, &randomized.skills.at(s.skill));
    d.mirror_skill = pairing(s.skill);
    skills.push_back(DescriptorJson(d));
  }
  metadata["skills"] = skills;
  return metadata;
}

void WriteSkillLibrary(const std::string& path, const TrainConfig& config, const TrainedPolicy& policy,
                       const Evaluation& evaluation, const Evaluation& randomized, const ExportProvenance& provenance) {
  SafeTensors file;
  // One string holds the whole description: safetensors metadata values must be strings.
  file.metadata["format"] = kSkillLibraryFormat;
  file.metadata["flsd"] = SkillLibraryMetadata(config, policy, evaluation, randomized, provenance).dump();
  AddNetwork(file, policy.policy->actor(), policy.normalizer, PolicyTensorPrefix(0), PolicyTensorPrefix(0) + "normalizer.");
  WriteSafeTensors(path, file);
}

nlohmann::json ExportRun(const std::string& run_dir, const std::string& path, int iteration) {
  namespace fs = std::filesystem;
  const TrainConfig config = LoadTrainConfig((fs::path(run_dir) / "config.yaml").string());
  const TrainedPolicy policy = LoadTrainedPolicy(config, RunCheckpoint(run_dir, iteration));
  const Evaluation evaluation = EvaluateSkills(config, policy.policy, policy.normalizer, EvaluationOptions{});
  EvaluationOptions randomize;
  randomize.randomize = true;
  const Evaluation randomized = EvaluateOverStarts(randomize, kRandomizedStarts, [&](const EvaluationOptions& o) {
    return EvaluateSkills(config, policy.policy, policy.normalizer, o);
  });
  const ExportProvenance provenance{run_dir, ReadCommits((fs::path(run_dir) / "commits").string()), FLSD_GIT_COMMIT};
  WriteSkillLibrary(path, config, policy, evaluation, randomized, provenance);
  return {{"library", path},
          {"method", config.method},
          {"num_skills", config.num_skills},
          {"iteration", policy.iteration},
          {"skills_surviving_500_steps", evaluation.survivors},
          {"skills_surviving_500_steps_randomized", randomized.survivors},
          {"state_coverage_rate", evaluation.coverage.rate}};
}

nlohmann::json ExportSelector(const std::string& run_dir, const std::string& path, int iteration) {
  namespace fs = std::filesystem;
  const std::string config_file = (fs::path(run_dir) / "config.yaml").string();
  const VelocityTrainConfig config = LoadVelocityTrainConfig(config_file);
  if (ParseVelocityMethod(config.method) != VelocityMethod::kSelector) {
    throw InputError(config_file + ": method is '" + config.method + "'; only a selector run can be exported");
  }
  const SkillLibrary base = SkillLibrary::Load(config.library);
  const TrainedSelector selector =
      LoadTrainedSelector(config, base.num_skills(), RunCheckpoint(run_dir, iteration));
  if (selector.library_fingerprint != base.fingerprint()) {
    throw InputError(run_dir + ": the selector was trained over a library with fingerprint " +
                     selector.library_fingerprint + ", but " + config.library + " now has " + base.fingerprint());
  }

  SafeTensors file = ReadSafeTensors(config.library);
  nlohmann::json metadata = base.metadata();
  AddNetwork(file, selector.policy->actor(), selector.normalizer, "selector.", "selector.normalizer.");
  const VelocityCommandConfig& commands = config.task.commands;
  const SelectorNetwork shape = SelectorShape(config);
  metadata["selector"] = {
      {"hidden", config.policy.actor_hidden},
      {"activation", "elu"},
      {"layers", config.policy.actor_hidden.size() + 1},
      {"decision_interval", shape.decision_interval},
      {"nearest_prior_temperature", shape.nearest_prior_temperature},
      {"time_sharing_prior", shape.time_sharing_prior},
      {"memory_window_steps", shape.memory_window_steps},
      {"observation",
       {{"motion", kMotionObsSize},
        {"command", kCommandSize},
        {"command_scale", {kMotionObsLayout[0].scale, kMotionObsLayout[0].scale, kMotionObsLayout[1].scale}}}},
      {"commands",
       {{"vx", {commands.vx.lo, commands.vx.hi}},
        {"vy", {commands.vy.lo, commands.vy.hi}},
        {"wz", {commands.wz.lo, commands.wz.hi}},
        {"min_planar_speed", commands.min_planar_speed}}},
      {"training",
       {{"iteration", selector.iteration},
        {"env_steps", selector.env_steps},
        {"config", ToYamlString(config)},
        {"run", run_dir},
        {"commits", ReadCommits((fs::path(run_dir) / "commits").string())},
        {"export_commit", FLSD_GIT_COMMIT}}},
  };
  // Evaluated through the file as skilld will read it: written once without the evaluation,
  // loaded and run with Eigen, then written with it.
  const std::string unevaluated = path + ".unevaluated";
  file.metadata["flsd"] = metadata.dump();
  WriteSafeTensors(unevaluated, file);
  TrackingEvaluation tracking;
  try {
    const SkillLibrary library = SkillLibrary::Load(unevaluated);
    // On the fixed set as `flsd track` runs it: the skills' own training env, whose terminations
    // say what a fall is (the selector's run may loosen them to train).
    tracking = EvaluateTracking(library, TrainingEnvOf(library), EvaluationTrackingCases(library), 10.0, 2.0,
                                kTrackingEnvSeed);
  } catch (...) {
    fs::remove(unevaluated);
    throw;
  }
  fs::remove(unevaluated);
  metadata["selector"]["evaluation"] = TrackingJson(tracking);
  file.metadata["flsd"] = metadata.dump();
  WriteSafeTensors(path, file);
  return {{"library", path},
          {"base_library", config.library},
          {"iteration", selector.iteration},
          {"env_steps", selector.env_steps},
          {"tracking", TrackingJson(tracking)}};
}

namespace {

// A scratch run's joint-level policy, its mean action on [o^c, previous action].
class ScratchController final : public TrackingController {
 public:
  explicit ScratchController(TrainedPolicy trained) : trained_(std::move(trained)) {}
  void Reset() override {}
  std::array<double, 3> Clip(const double* command) const override { return {command[0], command[1], command[2]}; }
  int Act(const float* motion_obs, const double* command, const float* previous_action, float* action) override {
    BuildTaskObservation(motion_obs, command, obs_.data());
    std::copy(previous_action, previous_action + kActionSize, obs_.begin() + kTaskObsSize);
    torch::NoGradGuard no_grad;
    const torch::Tensor mean =
        trained_.policy->ActionMean(trained_.normalizer->Normalize(torch::from_blob(obs_.data(), {1, kObs}))).contiguous();
    std::copy(mean.data_ptr<float>(), mean.data_ptr<float>() + kActionSize, action);
    return -1;
  }

 private:
  static constexpr int kObs = kTaskObsSize + kActionSize;
  TrainedPolicy trained_;
  std::array<float, kObs> obs_{};
};

struct CurvePoint {
  int iteration = 0;
  long env_steps = 0;
  nlohmann::json tracking;  // TrackingJson
};

// A selector run's checkpoint, exported to `library` and tracked through it: on its own library's
// evaluation set the export's evaluation, on `cases` another.
CurvePoint SelectorPoint(const std::string& run_dir, int iteration, const std::string& library,
                         const std::vector<TrackingCase>* cases) {
  const nlohmann::json exported = ExportSelector(run_dir, library, iteration);
  if (cases == nullptr) return {exported["iteration"], exported["env_steps"], exported["tracking"]};
  const SkillLibrary served = SkillLibrary::Load(library);
  return {exported["iteration"], exported["env_steps"],
          TrackingJson(EvaluateTracking(served, TrainingEnvOf(served), *cases, 10.0, 2.0, kTrackingEnvSeed))};
}

// A scratch run's checkpoint, on the simulated A1 it trained on without randomisation.
CurvePoint ScratchPoint(const VelocityTrainConfig& config, const std::string& run_dir, int iteration,
                        const std::vector<TrackingCase>& cases) {
  TrainedPolicy trained = LoadTrainedScratch(config, RunCheckpoint(run_dir, iteration));
  CurvePoint point{trained.iteration, trained.env_steps, {}};
  ScratchController controller(std::move(trained));
  point.tracking =
      TrackingJson(EvaluateController(controller, ServedEnvConfig(config.env, 0), cases, 10.0, 2.0, kTrackingEnvSeed));
  return point;
}

}  // namespace

nlohmann::json SelectorCurve(const std::string& run_dir, const std::string& cases_library) {
  namespace fs = std::filesystem;
  const VelocityTrainConfig config = LoadVelocityTrainConfig((fs::path(run_dir) / "config.yaml").string());
  const bool scratch = ParseVelocityMethod(config.method) == VelocityMethod::kScratch;
  if (scratch && cases_library.empty()) {
    throw InputError(run_dir + ": a scratch run chooses from no library; name the evaluation set's with --cases-from");
  }
  std::optional<std::vector<TrackingCase>> cases;
  if (!cases_library.empty()) cases = EvaluationTrackingCases(SkillLibrary::Load(cases_library));
  std::vector<int> iterations = KeptIterations(run_dir);
  iterations.push_back(0);  // the latest
  const std::string library = (fs::path(run_dir) / "selector_curve.safetensors.tmp").string();
  nlohmann::json rows = nlohmann::json::array();
  for (int iteration : iterations) {
    const CurvePoint p = scratch ? ScratchPoint(config, run_dir, iteration, *cases)
                                 : SelectorPoint(run_dir, iteration, library, cases ? &*cases : nullptr);
    if (iteration == 0 && !rows.empty() && rows.back()["iteration"] == p.iteration) continue;
    rows.push_back({{"iteration", p.iteration},
                    {"env_steps", p.env_steps},
                    {"rms_lin_error", p.tracking["rms_lin_error"]},
                    {"rms_ang_error", p.tracking["rms_ang_error"]},
                    {"falls", p.tracking["falls"]},
                    {"switches_per_s", p.tracking["switches_per_s"]}});
  }
  fs::remove(library);
  const nlohmann::json out = {
      {"run", run_dir}, {"cases_from", cases_library.empty() ? config.library : cases_library}, {"rows", rows}};
  WriteFileAtomically((fs::path(run_dir) / "selector_curve.json").string(), out.dump(2) + "\n");
  return out;
}

}  // namespace flsd
