// The velocity task and its two learners (the selector over the shipped skills, and the policy
// from scratch) on configs/selector_smoke.yaml: iterations, resume, the library fingerprint
// guard, and the exported selector's parity with libtorch.

#include "skills/learning/tasks/velocity_tracking_task.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <limits>

#include "core/paths.h"
#include "robot/observation.h"
#include "skills/learning/export/export.h"
#include "skills/learning/evaluation/tracking_eval.h"
#include "skills/learning/runners/training_run.h"
#include "skills/learning/tasks/velocity_command_env.h"
#include "skills/runtime/hierarchical_policy.h"
#include "skills/runtime/nearest_skill.h"
#include "skills/runtime/safetensors.h"
#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;
using testutil::InputErrorMessage;
namespace fs = std::filesystem;

class VelocityTraining : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testutil::UniqueTempPath("task");
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // The library is copied, so that a test may change it.
    library_ = Path("skills.safetensors");
    fs::copy_file(ResolveDataPath("models/a1_flsd.safetensors"), library_);
    config_ = LoadVelocityTrainConfig(ResolveDataPath("configs/selector_smoke.yaml"));
    config_.library = library_;
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (fs::path(dir_) / name).string(); }

  // A new run in `name` with config_, trained to `iterations`.
  int Train(const std::string& name, int iterations, bool resume = false) {
    const std::string config_file = Path(name + ".yaml");
    std::ofstream(config_file) << ToYamlString(config_);
    VelocityRunOptions options;
    options.config_path = config_file;
    options.run_dir = Path(name);
    options.resume = resume;
    options.iterations = iterations;
    std::atomic<bool> stop{false};
    return RunVelocityTraining(options, stop);
  }

  std::string dir_, library_;
  VelocityTrainConfig config_;
};

TEST(VelocityCommandEnv, CommandsAreRedrawnOnScheduleAndSeenScaledInTheObservation) {
  VelocityEnvConfig config;
  config.commands.resampling_s = 0.1;  // every 5 control steps
  config.commands.min_planar_speed = 0.0;
  EnvConfig env;
  env.randomization.DisableAll();
  VelocityCommandEnv task(env, config, 2, 7, 1);
  std::vector<float> actions(2 * kActionSize, 0.0f), obs(2 * kTaskObsSize);
  const Eigen::Vector3d first = task.command(0);
  for (int t = 0; t < 4; ++t) task.Step(actions.data());
  EXPECT_EQ(task.command(0), first) << "redrawn before its time";
  task.Step(actions.data());
  EXPECT_NE(task.command(0), first) << "not redrawn after 5 steps";
  task.WriteTaskObservations(obs.data());
  const Eigen::Vector3d c = task.command(1);
  EXPECT_FLOAT_EQ(obs[kTaskObsSize + kMotionObsSize + 0], 2.0 * c.x());  // o^m's base_lin_vel scale
  EXPECT_FLOAT_EQ(obs[kTaskObsSize + kMotionObsSize + 1], 2.0 * c.y());
  EXPECT_FLOAT_EQ(obs[kTaskObsSize + kMotionObsSize + 2], 0.25 * c.z());  // base_ang_vel scale
  EXPECT_FLOAT_EQ(obs[kTaskObsSize + 0], task.vec_env().motion_obs()[kMotionObsSize + 0]);
  // The reward is legged_gym's, on the state the step ended in: standing still under a command
  // to move earns the tracking terms' values for that error.
  const VelocityRewardTerms& terms = task.terms(0);
  EXPECT_GT(terms.tracking_lin_vel, 0.0);
  EXPECT_LE(terms.tracking_lin_vel, 1.0);
  EXPECT_GE(task.rewards()[0], 0.0f);
}

TEST_F(VelocityTraining, SelectorAndScratchRunsTrainResumeAndLogEveryIteration) {
  ASSERT_EQ(Train("selector", 2), 0);
  ASSERT_EQ(Train("selector", 3, /*resume=*/true), 0);
  std::ifstream progress(Path("selector/progress.csv"));
  std::string header, line;
  std::getline(progress, header);
  EXPECT_THAT(header, HasSubstr("mean_reward"));
  int rows = 0;
  for (; std::getline(progress, line); ++rows) EXPECT_EQ(std::stoi(line), rows + 1);
  EXPECT_EQ(rows, 3);

  config_.method = "scratch";
  ASSERT_EQ(Train("scratch", 2), 0);
  EXPECT_TRUE(fs::exists(Path("scratch/checkpoint.pt")));
}

// A selector trained on its rollouts' mirror images too, over commands drawn from what its
// library's skills do: the run records the envelope it drew from, and the scratch policy mirrors
// its joint actions the same way.
TEST_F(VelocityTraining, MirroredRunsOverTheLibrarysEnvelopeTrain) {
  config_.mirror = true;
  config_.task.commands.library_envelope = 1.1;
  config_.task.commands.zero_share = 0.2;
  ASSERT_EQ(Train("mirrored", 2), 0);
  const VelocityTrainConfig saved = LoadVelocityTrainConfig(Path("mirrored/config.yaml"));
  const std::array<Interval, 3> envelope = CommandEnvelope(SkillLibrary::Load(library_), 1.1);
  EXPECT_EQ(saved.task.commands.vx, envelope[0]);
  EXPECT_EQ(saved.task.commands.wz, envelope[2]);
  config_.method = "scratch";
  ASSERT_EQ(Train("mirrored_scratch", 2), 0);
  // Commands near the skills: the run records every dependable skill's (vx, vy, wz).
  config_.method = "selector";
  config_.task.commands.skill_share = 0.5;
  ASSERT_EQ(Train("near_skills", 1), 0);
  const NearestSkillSelector nearest(SkillLibrary::Load(library_));
  const std::vector<double> recorded = LoadVelocityTrainConfig(Path("near_skills/config.yaml")).task.commands.skill_velocities;
  ASSERT_EQ(recorded.size(), 3 * nearest.candidates().size());
  EXPECT_DOUBLE_EQ(recorded[3], nearest.velocities()[1].x());
  EXPECT_DOUBLE_EQ(recorded.back(), nearest.velocities().back().z());
}

// With reward streams the critic has two value heads: the run trains, resumes from its checkpoint,
// and exports (loading the two-headed critic back), and the scratch policy does the same.
TEST_F(VelocityTraining, RunsWithRewardStreamsTrainResumeAndExport) {
  config_.reward_streams = true;
  ASSERT_EQ(Train("streams", 2), 0);
  ASSERT_EQ(Train("streams", 3, /*resume=*/true), 0);
  TrainedSelector trained = LoadTrainedSelector(config_, SkillLibrary::Load(library_).num_skills(),
                                                Path("streams/checkpoint.pt"));
  {
    torch::NoGradGuard no_grad;
    const int columns = VelocityPolicyObsSize(config_, SkillLibrary::Load(library_).num_skills());
    EXPECT_EQ(trained.policy->Value(torch::zeros({5, columns})).sizes(), (std::vector<int64_t>{5, 2}));
  }
  ExportSelector(Path("streams"), Path("streams.safetensors"));
  EXPECT_TRUE(SkillLibrary::Load(Path("streams.safetensors")).selector().has_value());
  config_.method = "scratch";
  ASSERT_EQ(Train("streams_scratch", 2), 0);
}

TEST(VelocityCommandEnv, TheEnvelopeSpansTheSurvivingSkillsAndStill) {
  const SkillLibrary library = SkillLibrary::Load(ResolveDataPath("models/a1_flsd.safetensors"));
  const std::array<Interval, 3> envelope = CommandEnvelope(library, 1.0);
  double vx_min = 0.0, vx_max = 0.0;
  for (const SkillDescriptor& d : library.skills()) {
    if (!Dependable(d)) continue;
    vx_min = std::min(vx_min, d.mean_linear_velocity.x());
    vx_max = std::max(vx_max, d.mean_linear_velocity.x());
  }
  EXPECT_DOUBLE_EQ(envelope[0].lo, vx_min);
  EXPECT_DOUBLE_EQ(envelope[0].hi, vx_max);
  EXPECT_DOUBLE_EQ(CommandEnvelope(library, 1.5)[0].hi, 1.5 * vx_max);
  VelocityCommandConfig all_zero;
  all_zero.zero_share = 1.0;
  Rng rng(3);
  for (int k = 0; k < 10; ++k) EXPECT_EQ(SampleVelocityCommand(rng, all_zero), Eigen::Vector3d::Zero());
}

TEST_F(VelocityTraining, ASelectorIsNeverResumedOrExportedOverAChangedLibrary) {
  ASSERT_EQ(Train("selector", 1), 0);
  // Another library in the same place: one skill descriptor differs.
  SafeTensors file = ReadSafeTensors(library_);
  nlohmann::json metadata = nlohmann::json::parse(file.metadata["flsd"]);
  metadata["skills"][0]["mean_base_height"] = 0.5;
  file.metadata["flsd"] = metadata.dump();
  WriteSafeTensors(library_, file);
  EXPECT_THAT(InputErrorMessage([&] { Train("selector", 2, /*resume=*/true); }), HasSubstr("fingerprint"));
  EXPECT_THAT(InputErrorMessage([&] { ExportSelector(Path("selector"), Path("out.safetensors")); }),
              HasSubstr("fingerprint"));
}

TEST_F(VelocityTraining, TheExportedSelectorMatchesLibtorchAndRunsTheSkills) {
  ASSERT_EQ(Train("selector", 2), 0);
  const std::string out = Path("with_selector.safetensors");
  const nlohmann::json result = ExportSelector(Path("selector"), out);
  const SkillLibrary library = SkillLibrary::Load(out);
  ASSERT_TRUE(library.selector().has_value());
  const SkillLibrary base = SkillLibrary::Load(library_);
  EXPECT_EQ(library.num_skills(), base.num_skills());
  // Evaluated on the fixed evaluation set, which the library records.
  EXPECT_EQ(result["tracking"]["cases"].size(), EvaluationTrackingCases(base).size());
  EXPECT_EQ(library.metadata()["selector"]["evaluation"]["cases"].size(), EvaluationTrackingCases(base).size());

  TrainedSelector trained = LoadTrainedSelector(config_, base.num_skills(), Path("selector/checkpoint.pt"));
  torch::manual_seed(11);
  const torch::Tensor obs = torch::randn({16, kTaskObsSize}) * 2.0;
  torch::NoGradGuard no_grad;
  // The network's own logits: its prior columns zero.
  const int skills = library.num_skills();
  const torch::Tensor logits = trained.policy->Distribution(
      torch::cat({trained.normalizer->Normalize(obs), torch::zeros({obs.size(0), skills})}, 1));
  NetworkRunner runner(library.selector()->network);
  HierarchicalPolicy hierarchy(library);
  SelectorPrior masks(library, 0.0, 0.0);
  std::vector<float> out_logits(skills), mask(skills), action(kActionSize), previous(kActionSize, 0.0f);
  double worst = 0.0;
  for (int64_t i = 0; i < obs.size(0); ++i) {
    runner.Run(obs[i].data_ptr<float>(), out_logits.data());
    for (int k = 0; k < skills; ++k) {
      worst = std::max(worst, std::abs(double(out_logits[k]) - logits[i][k].item<double>()));
    }
    // From a stand, the hierarchy chooses the most probable skill the masks allow for the same o^c
    // (built from o^m and the command the observation encodes).
    const float* row = obs[i].data_ptr<float>();
    const double command[3] = {row[kMotionObsSize] / 2.0, row[kMotionObsSize + 1] / 2.0,
                               row[kMotionObsSize + 2] / 0.25};
    const std::array<double, 3> clipped = hierarchy.Clip(command);
    if (clipped[0] == command[0] && clipped[1] == command[1] && clipped[2] == command[2]) {
      hierarchy.Reset();
      const int skill = hierarchy.Act(row, command, previous.data(), action.data());
      masks.Write(command, -1, -1, mask.data());
      EXPECT_EQ(skill, (logits[i] + torch::tensor(mask)).argmax().item<int64_t>()) << "sample " << i;
    }
  }
  EXPECT_LT(worst, 1e-4) << "Eigen and libtorch selector logits differ";
}

// A selector trained to hold each skill for 3 control steps is served the same way: a choice on
// the first call and every third after, whatever the observations do in between; Reset forgets.
TEST_F(VelocityTraining, TheSelectorHoldsItsChoiceForItsDecisionInterval) {
  config_.decision_interval = 3;
  ASSERT_EQ(Train("held", 1), 0);
  const std::string out = Path("held.safetensors");
  ExportSelector(Path("held"), out);
  const SkillLibrary library = SkillLibrary::Load(out);
  ASSERT_EQ(library.selector()->decision_interval, 3);
  HierarchicalPolicy hierarchy(library);
  NetworkRunner selector(library.selector()->network);
  torch::manual_seed(5);
  const torch::Tensor motion = torch::randn({12, kMotionObsSize}) * 3.0;
  const double command[3] = {0.6, -0.4, 0.5};
  std::vector<float> action(kActionSize), previous(kActionSize, 0.0f), obs(kTaskObsSize), logits(library.num_skills());
  for (int call = 0; call < 12; ++call) {
    const float* m = motion[call].data_ptr<float>();
    const int chosen = hierarchy.Act(m, command, previous.data(), action.data());
    const int decision = call - call % 3;  // the call that made this choice
    BuildTaskObservation(motion[decision].data_ptr<float>(), command, obs.data());
    selector.Run(obs.data(), logits.data());
    EXPECT_EQ(chosen, std::max_element(logits.begin(), logits.end()) - logits.begin()) << "call " << call;
  }
  hierarchy.Reset();
  BuildTaskObservation(motion[1].data_ptr<float>(), command, obs.data());
  selector.Run(obs.data(), logits.data());
  const int best = static_cast<int>(std::max_element(logits.begin(), logits.end()) - logits.begin());
  EXPECT_EQ(hierarchy.Act(motion[1].data_ptr<float>(), command, previous.data(), action.data()), best);

  // Nor does it make a switch the library records a fall for: after the skill still running at a
  // reset, the next most probable.
  const int running = best == 0 ? 1 : 0;
  SafeTensors file = ReadSafeTensors(out);
  nlohmann::json meta = nlohmann::json::parse(file.metadata["flsd"]);
  meta["transitions"]["falls"] = {{running, best}};
  file.metadata["flsd"] = meta.dump();
  WriteSafeTensors(out, file);
  const SkillLibrary guarded = SkillLibrary::Load(out);
  HierarchicalPolicy careful(guarded);
  careful.Reset(running);
  logits[best] = -std::numeric_limits<float>::infinity();
  EXPECT_EQ(careful.Act(motion[1].data_ptr<float>(), command, previous.data(), action.data()),
            std::max_element(logits.begin(), logits.end()) - logits.begin());
}

// With a nearest-skill prior the selector's logits are its network's plus the prior of the command
// (NearestSkillSelector::Prior), in training (mirrored rollouts too) and as skilld serves it.
// A semi-MDP selector (1 decision per 5 control steps here, a 0.2-s memory window, a time-sharing
// prior) is served as it was trained: skilld's HierarchicalPolicy keeps the same memory and prior
// and chooses what the libtorch policy's most probable skill is, on the same observations.
TEST_F(VelocityTraining, ASemiMdpSelectorIsServedWithItsMemoryPriorAndHold) {
  config_.decision_interval = 5;
  config_.semi_mdp.window_s = 0.2;
  config_.time_sharing_prior = 3.0;
  config_.discount_per_second = 0.5;
  EXPECT_NEAR(VelocityPpoConfig(config_).gamma, std::pow(0.5, 0.1), 1e-12);  // per 0.1-s decision
  ASSERT_EQ(Train("semi_mdp", 2), 0);
  const std::string out = Path("semi_mdp.safetensors");
  ExportSelector(Path("semi_mdp"), out);
  const SkillLibrary library = SkillLibrary::Load(out);
  const SelectorNetwork& served = *library.selector();
  EXPECT_EQ(served.decision_interval, 5);
  EXPECT_EQ(served.memory_window_steps, 10);
  EXPECT_EQ(served.time_sharing_prior, 3.0);

  const int skills = library.num_skills(), inputs = served.inputs(skills);
  TrainedSelector trained = LoadTrainedSelector(config_, skills, Path("semi_mdp/checkpoint.pt"));
  HierarchicalPolicy hierarchy(library);
  SelectorMemory memory(10);
  SelectorPrior prior(library, 0.0, 3.0);
  torch::manual_seed(17);
  const torch::Tensor motion = torch::randn({20, kMotionObsSize});
  const double command[3] = {0.3, 0.1, -0.4};  // within the trained ranges
  ASSERT_EQ(hierarchy.Clip(command), (std::array<double, 3>{0.3, 0.1, -0.4}));
  std::vector<float> row(inputs + skills), action(kActionSize), previous(kActionSize, 0.0f);
  torch::NoGradGuard no_grad;
  int expected = -1;
  for (int t = 0; t < 20; ++t) {
    const float* m = motion[t].data_ptr<float>();
    if (t % 5 == 0) {
      BuildTaskObservation(m, command, row.data());
      memory.WriteFeatures(skills, row.data() + kTaskObsSize);
      prior.Write(command, memory.previous(), memory.running(), row.data() + inputs);
      const torch::Tensor raw = torch::tensor(row).unsqueeze(0);
      const int normalized = served.normalized_inputs();
      const torch::Tensor obs = torch::cat(
          {trained.normalizer->Normalize(raw.narrow(1, 0, normalized)), raw.narrow(1, normalized, row.size() - normalized)}, 1);
      expected = static_cast<int>(trained.policy->Distribution(obs)[0].argmax().item<int64_t>());
    }
    EXPECT_EQ(hierarchy.Act(m, command, previous.data(), action.data()), expected) << "step " << t;
    memory.Record(command, expected, m);
  }

  config_.mirror = true;
  EXPECT_THAT(InputErrorMessage([&] { ValidateVelocityTrainConfig(config_, "c"); }),
              HasSubstr("the time-sharing prior and the semi-MDP memory are not mirrored"));
}

// Fig. 8's Scratch on the semi-MDP selector's task: the same reward, every control step, no prior.
TEST_F(VelocityTraining, TheScratchPolicyTrainsOnTheSemiMdpReward) {
  config_.method = "scratch";
  config_.semi_mdp.window_s = 0.2;
  config_.time_sharing_prior = 3.0;
  EXPECT_THAT(InputErrorMessage([&] { ValidateVelocityTrainConfig(config_, "c"); }),
              HasSubstr("a prior over skills needs method 'selector'"));
  config_.time_sharing_prior = 0.0;
  ASSERT_EQ(Train("semi_mdp_scratch", 1), 0);
  // Evaluated on a library's evaluation set, which it must be told.
  EXPECT_THAT(InputErrorMessage([&] { SelectorCurve(Path("semi_mdp_scratch")); }), HasSubstr("--cases-from"));
  const nlohmann::json curve = SelectorCurve(Path("semi_mdp_scratch"), library_);
  ASSERT_EQ(curve["rows"].size(), 1u);
  EXPECT_EQ(curve["rows"][0]["iteration"], 1);
  EXPECT_GT(curve["rows"][0]["rms_lin_error"].get<double>(), 0.0);
  EXPECT_EQ(curve["rows"][0]["switches_per_s"], 0.0);  // no skills to switch
}

// The evaluation over training: each kept checkpoint and the latest, exported and tracked on
// the fixed evaluation set, in order of the env steps they had trained on.
TEST_F(VelocityTraining, TheSelectorCurveTracksEachKeptCheckpoint) {
  config_.keep_checkpoint_every = 1;
  ASSERT_EQ(Train("curve", 2), 0);
  const nlohmann::json curve = SelectorCurve(Path("curve"));
  ASSERT_EQ(curve["rows"].size(), 2u);  // iterations 1 and 2 (the latest is 2)
  EXPECT_EQ(curve["rows"][0]["iteration"], 1);
  EXPECT_EQ(curve["rows"][1]["iteration"], 2);
  EXPECT_LT(curve["rows"][0]["env_steps"].get<long>(), curve["rows"][1]["env_steps"].get<long>());
  EXPECT_GT(curve["rows"][1]["rms_lin_error"].get<double>(), 0.0);
  EXPECT_TRUE(fs::exists(Path("curve/selector_curve.json")));
  EXPECT_FALSE(fs::exists(Path("curve/selector_curve.safetensors.tmp")));
}

// The export's evaluation is the fixed set's as `flsd track` runs it, on the skills' own env, not
// on the selector run's: here the run's env would call every step a fall (a base below 0.9 m).
TEST_F(VelocityTraining, TheExportIsEvaluatedOnTheFixedSetsEnvNotTheRunsOwn) {
  config_.env.termination.limits.min_base_height = 0.9;
  ASSERT_EQ(Train("own_env", 1), 0);
  const std::string out = Path("own_env.safetensors");
  const nlohmann::json exported = ExportSelector(Path("own_env"), out);
  const SkillLibrary library = SkillLibrary::Load(out);
  const TrackingEvaluation fixed = EvaluateTracking(library, TrainingEnvOf(library), EvaluationTrackingCases(library),
                                                    10.0, 2.0, kTrackingEnvSeed, SelectorKind::kLearned);
  EXPECT_LT(fixed.falls, static_cast<int>(EvaluationTrackingCases(library).size()));
  EXPECT_EQ(exported["tracking"]["falls"].get<int>(), fixed.falls);
  EXPECT_DOUBLE_EQ(exported["tracking"]["rms_lin_error"].get<double>(), fixed.rms_lin_error);
  EXPECT_DOUBLE_EQ(exported["tracking"]["rms_ang_error"].get<double>(), fixed.rms_ang_error);
}

TEST_F(VelocityTraining, ASelectorWithANearestSkillPriorIsServedWithTheSamePrior) {
  config_.nearest_prior_temperature = 0.05;
  config_.mirror = true;
  ASSERT_EQ(Train("prior", 2), 0);
  const std::string out = Path("prior.safetensors");
  ExportSelector(Path("prior"), out);
  const SkillLibrary library = SkillLibrary::Load(out);
  ASSERT_EQ(library.selector()->nearest_prior_temperature, 0.05);
  const NearestSkillSelector nearest(library);
  TrainedSelector trained = LoadTrainedSelector(config_, library.num_skills(), Path("prior/checkpoint.pt"));
  HierarchicalPolicy hierarchy(library);
  torch::manual_seed(13);
  const torch::Tensor motion = torch::randn({16, kMotionObsSize});
  std::vector<float> obs(kTaskObsSize), prior(library.num_skills()), action(kActionSize), previous(kActionSize, 0.0f);
  torch::NoGradGuard no_grad;
  int nearest_chosen = 0;
  for (int i = 0; i < 16; ++i) {
    const double raw[3] = {-1.5 + 0.2 * i, 0.7 - 0.09 * i, 0.8 - 0.1 * i};
    const std::array<double, 3> command = hierarchy.Clip(raw);
    BuildTaskObservation(motion[i].data_ptr<float>(), command.data(), obs.data());
    nearest.Prior(command.data(), 0.05, prior.data());
    const torch::Tensor row = torch::cat({trained.normalizer->Normalize(torch::tensor(obs).unsqueeze(0)),
                                          torch::tensor(prior).unsqueeze(0)}, 1);
    const torch::Tensor logits = trained.policy->Distribution(row)[0];
    hierarchy.Reset();
    const int chosen = hierarchy.Act(motion[i].data_ptr<float>(), command.data(), previous.data(), action.data());
    EXPECT_EQ(chosen, logits.argmax().item<int64_t>()) << "command " << i;
    EXPECT_GT(prior[chosen], NearestSkillSelector::kExcludedLogit) << "an undependable skill, command " << i;
    nearest_chosen += chosen == nearest.Choose(command.data());
  }
  EXPECT_GE(nearest_chosen, 8) << "mostly the nearest skill";
  config_.method = "scratch";
  EXPECT_THAT(InputErrorMessage([&] { Train("scratch_prior", 1); }), HasSubstr("nearest_prior_temperature"));
}

TEST_F(VelocityTraining, ExportingAScratchRunIsRefused) {
  config_.method = "scratch";
  ASSERT_EQ(Train("scratch", 1), 0);
  config_.decision_interval = 2;
  EXPECT_THAT(InputErrorMessage([&] { Train("scratch2", 1); }), HasSubstr("decision_interval"));
  EXPECT_THAT(InputErrorMessage([&] { ExportSelector(Path("scratch"), Path("out.safetensors")); }),
              HasSubstr("only a selector run"));
}

}  // namespace
}  // namespace flsd
