// Algorithm 1 end to end on configs/smoke.yaml (8 envs x 24 steps, 4 skills, 32-wide nets):
// iterations, checkpoints, a run folder with resume, evaluation and the exported skill library.

#include <algorithm>
#include "skills/learning/runners/training_run.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/paths.h"
#include "robot/a1.h"
#include "robot/observation.h"
#include "skills/learning/evaluation/evaluation.h"
#include "skills/learning/evaluation/library_bar.h"
#include "server/safety.h"
#include "skills/learning/export/export.h"
#include "skills/learning/runners/run_folder.h"
#include "skills/learning/runners/training_run.h"
#include "skills/runtime/safetensors.h"
#include "tests/common/test_support.h"
#include "tests/common/in_memory_run.h"
#include "tests/common/served_termination.h"

namespace flsd {
namespace {

using testutil::TerminationOf;

using ::testing::AllOf;
using ::testing::HasSubstr;
using testutil::InputErrorMessage;
namespace fs = std::filesystem;

TrainConfig SmokeConfig() { return LoadTrainConfig(ResolveDataPath("configs/smoke.yaml")); }

// One smoke iteration: 8 envs x 24 steps.
constexpr long kStepsPerIteration = 8 * 24;

// Each test trains in a folder of its own.
class TrainingRun : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testutil::UniqueTempPath("run");
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (fs::path(dir_) / name).string(); }

  std::string dir_;
};

std::vector<std::string> Lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The iteration column of progress.csv, after checking its header.
std::vector<int> ProgressIterations(const std::string& path) {
  const std::vector<std::string> lines = Lines(path);
  EXPECT_FALSE(lines.empty());
  if (lines.empty()) return {};
  EXPECT_EQ(lines[0].rfind("iteration,env_steps,", 0), 0u) << lines[0];
  std::vector<int> iterations;
  for (size_t i = 1; i < lines.size(); ++i) {
    iterations.push_back(std::stoi(lines[i].substr(0, lines[i].find(','))));
  }
  return iterations;
}

// Every parameter and buffer of `a` equals (torch::equal) the one of the same name in `b`;
// failures name the tensor.
::testing::AssertionResult SameTensors(const torch::nn::Module& a, const torch::nn::Module& b) {
  auto compare = [](const torch::OrderedDict<std::string, torch::Tensor>& x,
                    const torch::OrderedDict<std::string, torch::Tensor>& y) -> ::testing::AssertionResult {
    if (x.size() != y.size()) return ::testing::AssertionFailure() << "different numbers of tensors";
    for (const auto& item : x) {
      const torch::Tensor* other = y.find(item.key());
      if (other == nullptr) return ::testing::AssertionFailure() << item.key() << " missing";
      if (!torch::equal(item.value(), *other)) return ::testing::AssertionFailure() << item.key() << " differs";
    }
    return ::testing::AssertionSuccess();
  };
  ::testing::AssertionResult parameters = compare(a.named_parameters(), b.named_parameters());
  if (!parameters) return parameters;
  return compare(a.named_buffers(), b.named_buffers());
}

// What a checkpoint holds for one Adam(W) optimiser, per parameter in parameter order.
struct OptimizerRecord {
  double learning_rate = 0.0;
  std::vector<int64_t> steps;  // 0 where the parameter has no state
  std::vector<torch::Tensor> exp_avg, exp_avg_sq;
};

// Reads it back through an optimiser of type O over stand-in parameters of the same shapes:
// the saved state is keyed by tensor addresses, which torch's load maps onto parameters by
// position, so two trainers' checkpoints become comparable.
template <class O, class State>
OptimizerRecord ReadOptimizer(const std::string& checkpoint, const char* key,
                              const torch::nn::Module& shapes) {
  std::vector<torch::Tensor> params;
  for (const torch::Tensor& p : shapes.parameters()) params.push_back(torch::zeros_like(p).requires_grad_());
  O optimizer(params);
  torch::serialize::InputArchive archive, sub;
  archive.load_from(checkpoint);
  archive.read(key, sub);
  optimizer.load(sub);
  OptimizerRecord r;
  r.learning_rate = optimizer.param_groups()[0].options().get_lr();
  for (const torch::Tensor& p : params) {
    const auto it = optimizer.state().find(c10::guts::to_string(p.unsafeGetTensorImpl()));
    if (it == optimizer.state().end()) {
      r.steps.push_back(0);
      r.exp_avg.emplace_back();
      r.exp_avg_sq.emplace_back();
      continue;
    }
    const State& s = static_cast<const State&>(*it->second);
    r.steps.push_back(s.step());
    r.exp_avg.push_back(s.exp_avg());
    r.exp_avg_sq.push_back(s.exp_avg_sq());
  }
  return r;
}

OptimizerRecord AdamRecord(const std::string& checkpoint, const char* key, const torch::nn::Module& shapes) {
  return ReadOptimizer<torch::optim::Adam, torch::optim::AdamParamState>(checkpoint, key, shapes);
}
OptimizerRecord AdamWRecord(const std::string& checkpoint, const char* key, const torch::nn::Module& shapes) {
  return ReadOptimizer<torch::optim::AdamW, torch::optim::AdamWParamState>(checkpoint, key, shapes);
}

void ExpectSameOptimizer(const OptimizerRecord& a, const OptimizerRecord& b, const std::string& name) {
  EXPECT_EQ(a.learning_rate, b.learning_rate) << name;
  ASSERT_EQ(a.steps, b.steps) << name;
  for (size_t i = 0; i < a.steps.size(); ++i) {
    if (a.steps[i] == 0) continue;
    EXPECT_TRUE(torch::equal(a.exp_avg[i], b.exp_avg[i])) << name << " exp_avg of parameter " << i;
    EXPECT_TRUE(torch::equal(a.exp_avg_sq[i], b.exp_avg_sq[i])) << name << " exp_avg_sq of parameter " << i;
  }
}

c10::IValue ReadValue(const std::string& checkpoint, const char* key) {
  torch::serialize::InputArchive archive;
  archive.load_from(checkpoint);
  c10::IValue value;
  archive.read(key, value);
  return value;
}

TEST_F(TrainingRun, IterationReportsFiniteStatsAndCountsSteps) {
  testutil::SkillRun trainer(SmokeConfig());
  EXPECT_EQ(trainer.runner.iteration(), 0);
  EXPECT_EQ(trainer.task.shape().obs, PolicyObservationSize(4));
  const RunnerStats s = trainer.runner.RunIteration();
  const SkillDiscoveryStats& task_stats = trainer.task.stats();
  EXPECT_TRUE(s.finite);
  EXPECT_TRUE(s.ppo.finite);
  EXPECT_EQ(s.iteration, 1);
  EXPECT_EQ(trainer.runner.iteration(), 1);
  EXPECT_EQ(s.env_steps, kStepsPerIteration);
  EXPECT_EQ(trainer.runner.env_steps(), kStepsPerIteration);
  EXPECT_GE(task_stats.discriminator_accuracy, 0.0);
  EXPECT_LE(task_stats.discriminator_accuracy, 1.0);
  // Eq. 11 is log q - log p <= log N_k.
  EXPECT_TRUE(std::isfinite(task_stats.intrinsic_reward));
  EXPECT_LE(task_stats.intrinsic_reward, std::log(4.0) + 1e-6);
  EXPECT_TRUE(std::isfinite(task_stats.pae_loss) && task_stats.pae_loss > 0.0) << task_stats.pae_loss;
  EXPECT_TRUE(std::isfinite(task_stats.discriminator_loss) && task_stats.discriminator_loss > 0.0) << task_stats.discriminator_loss;
  EXPECT_TRUE(std::isfinite(s.ppo.surrogate_loss) && std::isfinite(s.ppo.value_loss) &&
              std::isfinite(s.ppo.kl));
  EXPECT_GE(s.ppo.learning_rate, 1e-5);
  EXPECT_LE(s.ppo.learning_rate, 1e-2);
  EXPECT_GT(task_stats.action_std, 0.0);
  EXPECT_GE(task_stats.fall_fraction, 0.0);
  EXPECT_LE(task_stats.fall_fraction, 1.0);
  EXPECT_GT(s.seconds_total, 0.0);
  EXPECT_GT(trainer.runner.normalizer()->count(), 0.0);  // o^p statistics were gathered
  const RunnerStats second = trainer.runner.RunIteration();
  EXPECT_EQ(second.iteration, 2);
  EXPECT_EQ(second.env_steps, 2 * kStepsPerIteration);
}

// A resumed run must continue from exactly the saved state: networks, normaliser, the three
// optimisers, counters and random states.
TEST_F(TrainingRun, CheckpointRestoresEverythingExactly) {
  const TrainConfig config = SmokeConfig();
  testutil::SkillRun a(config);
  a.runner.RunIteration();
  a.runner.RunIteration();
  a.runner.SaveCheckpoint(Path("a.pt"));
  const torch::Tensor next_random = torch::rand({4});  // what the global generator gives next

  testutil::SkillRun b(config);
  ASSERT_FALSE(SameTensors(*a.task.actor_critic(), *b.task.actor_critic())) << "a fresh trainer must start elsewhere for this test";
  ASSERT_FALSE(SameTensors(*a.runner.normalizer(), *b.runner.normalizer()));
  b.runner.LoadCheckpoint(Path("a.pt"));
  EXPECT_TRUE(SameTensors(*a.task.actor_critic(), *b.task.actor_critic()));
  EXPECT_TRUE(SameTensors(*a.runner.normalizer(), *b.runner.normalizer()));
  EXPECT_TRUE(SameTensors(*a.task.pae(), *b.task.pae()));
  EXPECT_TRUE(SameTensors(*a.task.discriminator(), *b.task.discriminator()));
  EXPECT_EQ(b.runner.iteration(), 2);
  EXPECT_EQ(b.runner.env_steps(), 2 * kStepsPerIteration);

  // What b saves straight after loading must be what a saved.
  b.runner.SaveCheckpoint(Path("b.pt"));
  EXPECT_TRUE(torch::equal(torch::rand({4}), next_random)) << "torch's generator state was not restored";
  for (const char* key : {"iteration", "env_steps", "learning_rate", "skill_rng", "config"}) {
    EXPECT_EQ(ReadValue(Path("a.pt"), key), ReadValue(Path("b.pt"), key)) << key;
  }
  EXPECT_TRUE(torch::equal(ReadValue(Path("a.pt"), "torch_rng").toTensor(),
                           ReadValue(Path("b.pt"), "torch_rng").toTensor()));

  const OptimizerRecord policy_a = AdamRecord(Path("a.pt"), "policy_optimizer", *a.task.actor_critic());
  const OptimizerRecord pae_a = AdamWRecord(Path("a.pt"), "pae_optimizer", *a.task.pae());
  const OptimizerRecord disc_a = AdamRecord(Path("a.pt"), "discriminator_optimizer", *a.task.discriminator());
  ExpectSameOptimizer(policy_a, AdamRecord(Path("b.pt"), "policy_optimizer", *b.task.actor_critic()), "policy");
  ExpectSameOptimizer(pae_a, AdamWRecord(Path("b.pt"), "pae_optimizer", *b.task.pae()), "pae");
  ExpectSameOptimizer(disc_a, AdamRecord(Path("b.pt"), "discriminator_optimizer", *b.task.discriminator()),
                      "discriminator");
  // The state is not trivially empty: the smoke config's update counts over two iterations.
  // PPO: 5 epochs x 4 minibatches; PAE: a quarter of 192 windows in one minibatch of 64;
  // discriminator: 192 samples in minibatches of 64.
  EXPECT_EQ(policy_a.steps.front(), 2 * 5 * 4);
  EXPECT_EQ(pae_a.steps.front(), 2 * 1);
  EXPECT_EQ(disc_a.steps.front(), 2 * 3);
}

TEST_F(TrainingRun, LoadingAMismatchedCheckpointIsAnInputError) {
  TrainConfig config = SmokeConfig();
  testutil::SkillRun a(config);
  a.runner.SaveCheckpoint(Path("a.pt"));
  config.num_skills = 5;  // a 50-wide policy input and 5 discriminator outputs
  testutil::SkillRun b(config);
  EXPECT_THAT(InputErrorMessage([&] { b.runner.LoadCheckpoint(Path("missing.pt")); }), HasSubstr("missing.pt"));
  // torch's Module::load replaces each tensor whatever its shape; the trainer must refuse and keep
  // its own networks.
  EXPECT_THAT(InputErrorMessage([&] { b.runner.LoadCheckpoint(Path("a.pt")); }), HasSubstr("does not fit"));
  EXPECT_EQ(b.task.actor_critic()->named_parameters()["actor.0.weight"].sizes(),
            torch::IntArrayRef({32, PolicyObservationSize(5)}))
      << "the trainer's policy no longer fits its own config (its next RunIteration throws c10::Error)";
  EXPECT_EQ(b.task.discriminator()->parameters().back().sizes(), torch::IntArrayRef({5}));
  // The same gap in what eval and export load.
  EXPECT_THAT(InputErrorMessage([&] { LoadTrainedPolicy(config, Path("a.pt")); }), HasSubstr("does not fit"));
}

// A NaN anywhere in the policy must surface as a non-finite iteration, not as a silent update:
// in the critic it poisons the returns, in the actor the actions (which the simulator refuses).
TEST_F(TrainingRun, NanInThePolicyMakesTheIterationNonFinite) {
  const TrainConfig config = SmokeConfig();
  for (const char* name : {"critic.0.weight", "actor.0.weight"}) {
    testutil::SkillRun trainer(config);
    {
      torch::NoGradGuard no_grad;
      trainer.task.actor_critic()->named_parameters()[name][0][0].fill_(NAN);
    }
    const RunnerStats s = trainer.runner.RunIteration();
    EXPECT_FALSE(s.finite) << name;
    EXPECT_FALSE(s.ppo.finite) << name;
  }
}

// The config's seed must decide the initial networks: two trainers built from one config start
// alike whatever torch's global generator held before, and another seed starts elsewhere.
TEST_F(TrainingRun, InitialNetworksFollowTheConfigSeed) {
  TrainConfig config = SmokeConfig();
  torch::manual_seed(123);
  testutil::SkillRun a(config);
  torch::manual_seed(456);
  testutil::SkillRun b(config);
  config.seed = 2;
  torch::manual_seed(123);
  testutil::SkillRun c(config);
  EXPECT_TRUE(SameTensors(*a.task.actor_critic(), *b.task.actor_critic())) << "the initial networks must follow config.seed";
  EXPECT_FALSE(SameTensors(*a.task.actor_critic(), *c.task.actor_critic())) << "seeds 1 and 2 must start from different networks";
}

TEST_F(TrainingRun, RunsThenRefusesToOverwriteThenResumes) {
  const std::atomic<bool> stop{false};
  TrainingRunOptions options;
  options.config_path = ResolveDataPath("configs/smoke.yaml");
  options.run_dir = dir_;
  ASSERT_EQ(RunTraining(options, stop), 0);
  for (const char* file : {"config.yaml", "checkpoint.pt", "progress.csv", "commits"}) {
    EXPECT_TRUE(fs::exists(Path(file))) << file;
  }
  EXPECT_EQ(ProgressIterations(Path("progress.csv")), (std::vector<int>{1, 2, 3, 4}));
  EXPECT_EQ(ToYamlString(LoadTrainConfig(Path("config.yaml"))), ToYamlString(SmokeConfig()));
  EXPECT_EQ(Lines(Path("commits")).size(), 1u);
  EXPECT_EQ(ReadValue(Path("checkpoint.pt"), "iteration").toInt(), 4);

  EXPECT_THAT(InputErrorMessage([&] { RunTraining(options, stop); }), HasSubstr("--resume"));

  // A row past the checkpoint, as a run that died after iteration 5 but before saving leaves it:
  // the resumed run must replace it, not repeat it.
  {
    std::ofstream progress(Path("progress.csv"), std::ios::app);
    progress << "5,123456,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0\n";
  }
  options.resume = true;
  options.iterations = 6;
  ASSERT_EQ(RunTraining(options, stop), 0);
  EXPECT_EQ(ProgressIterations(Path("progress.csv")), (std::vector<int>{1, 2, 3, 4, 5, 6}));
  const std::vector<std::string> rows = Lines(Path("progress.csv"));
  EXPECT_EQ(rows.at(5).rfind("5," + std::to_string(5 * kStepsPerIteration) + ",", 0), 0u) << rows.at(5);
  const std::vector<std::string> commits = Lines(Path("commits"));
  ASSERT_EQ(commits.size(), 2u);
  EXPECT_THAT(commits[1], HasSubstr("(resumed)"));
  const TrainedPolicy trained = LoadTrainedPolicy(LoadTrainConfig(Path("config.yaml")), Path("checkpoint.pt"));
  EXPECT_EQ(trained.iteration, 6);
  EXPECT_EQ(trained.env_steps, 6 * kStepsPerIteration);
}

TEST_F(TrainingRun, ResumeWithoutACheckpointIsAnInputError) {
  TrainingRunOptions options;
  options.run_dir = dir_;
  options.resume = true;
  const std::atomic<bool> stop{false};
  EXPECT_THAT(InputErrorMessage([&] { RunTraining(options, stop); }), HasSubstr("nothing to resume"));
}

double Elu(double x) { return x > 0.0 ? x : std::expm1(x); }

// The policy's mean action computed from the library's tensors alone, in plain C++, as a robot
// computer without libtorch would: normalise the first 45 entries, then Linear + ELU layers and
// a last Linear layer.
std::vector<double> MeanActionByHand(const SafeTensors& library, int layers, const std::vector<float>& obs) {
  const FloatTensor& mean = library.tensors.at("policies.0.normalizer.mean");
  const FloatTensor& std = library.tensors.at("policies.0.normalizer.std");
  std::vector<double> x(obs.begin(), obs.end());
  for (size_t i = 0; i < mean.values.size(); ++i) x[i] = (x[i] - mean.values[i]) / std.values[i];
  for (int l = 0; l < layers; ++l) {
    const FloatTensor& w = library.tensors.at("policies.0.layer" + std::to_string(l) + ".weight");
    const FloatTensor& b = library.tensors.at("policies.0.layer" + std::to_string(l) + ".bias");
    const int64_t rows = w.shape[0], cols = w.shape[1];
    std::vector<double> y(rows);
    for (int64_t r = 0; r < rows; ++r) {
      double sum = b.values[r];
      for (int64_t c = 0; c < cols; ++c) sum += static_cast<double>(w.values[r * cols + c]) * x[c];
      y[r] = l + 1 < layers ? Elu(sum) : sum;
    }
    x = y;
  }
  return x;
}

// Every recorded point of a skill that did not fall belongs to its one episode: the env must not
// have been reset inside the record. A reset pose of the nominal robot has all joint velocities
// exactly zero, which a moving policy never has.
TEST_F(TrainingRun, EvaluationRecordsOneEpisodePerSkill) {
  const TrainConfig config = SmokeConfig();
  testutil::SkillRun trainer(config);
  EvaluationOptions options;
  options.steps = 40;
  const Evaluation eval = EvaluateSkills(config, trainer.task.actor_critic(), trainer.runner.normalizer(), options);
  ASSERT_EQ(eval.trajectories.size(), static_cast<size_t>(config.num_skills));
  int checked = 0;
  for (const SkillTrajectory& t : eval.trajectories) {
    if (t.fell) continue;
    ++checked;
    ASSERT_EQ(t.points.size(), 40u) << "skill " << t.skill;
    const auto& last = t.points.back().joint_velocity;
    EXPECT_FALSE(std::all_of(last.begin(), last.end(), [](double v) { return v == 0.0; }))
        << "skill " << t.skill << " ends on a reset pose";
    // Commanded its own mean velocity, a skill tracks it partly (the terms pay at most 1 + 0.5
    // per second), and a random policy's penalties are not zero.
    const VelocityRewardTerms& task = eval.skills[t.skill].task_reward_per_s;
    EXPECT_GT(task.tracking_lin_vel + task.tracking_ang_vel, 0.0) << "skill " << t.skill;
    EXPECT_LE(task.tracking_lin_vel + task.tracking_ang_vel, 1.5) << "skill " << t.skill;
    EXPECT_LT(task.action_rate, 0.0) << "skill " << t.skill;
    EXPECT_LT(task.total, task.tracking_lin_vel + task.tracking_ang_vel) << "skill " << t.skill;
  }
  EXPECT_GT(checked, 0) << "no skill stood for 40 steps: nothing was checked";
}

// Over three randomised starts: per skill, the shortest survival of the three evaluations run one
// by one from those seeds, a fall in any, and the mean of their stance-foot slips; the rest is the
// first's.
TEST_F(TrainingRun, OverStartsKeepsTheShortestSurvivalAndTheMeanSlip) {
  const TrainConfig config = SmokeConfig();
  testutil::SkillRun trainer(config);
  EvaluationOptions options{true, 500, 5};
  const Evaluation over = EvaluateOverStarts(options, 3, [&](const EvaluationOptions& o) {
    return EvaluateSkills(config, trainer.task.actor_critic(), trainer.runner.normalizer(), o);
  });
  EXPECT_EQ(over.starts, 3);
  std::vector<Evaluation> each;
  for (uint64_t seed : {5, 6, 7}) {
    options.seed = seed;
    each.push_back(EvaluateSkills(config, trainer.task.actor_critic(), trainer.runner.normalizer(), options));
  }
  bool differ = false;
  for (int k = 0; k < config.num_skills; ++k) {
    const SkillSummary &a = each[0].skills[k], &b = each[1].skills[k], &c = each[2].skills[k];
    const int shortest = std::min({a.survival_steps, b.survival_steps, c.survival_steps});
    EXPECT_EQ(over.skills[k].survival_steps, shortest) << "skill " << k;
    EXPECT_EQ(over.skills[k].fell, a.fell || b.fell || c.fell);
    EXPECT_NEAR(over.skills[k].mean_stance_foot_speed,
                (a.mean_stance_foot_speed + b.mean_stance_foot_speed + c.mean_stance_foot_speed) / 3.0, 1e-12);
    EXPECT_EQ(over.skills[k].mean_base_height, a.mean_base_height);
    differ |= shortest != a.survival_steps;
  }
  EXPECT_TRUE(differ) << "an untrained policy should fall sooner from some start: nothing was checked";
}

TEST(ParseIteration, TakesOneToNineDigitsAndNothingElse) {
  EXPECT_EQ(ParseIteration("4125"), 4125);
  EXPECT_EQ(ParseIteration("999999999"), 999999999);
  EXPECT_EQ(ParseIteration(""), std::nullopt);
  EXPECT_EQ(ParseIteration("1000000000"), std::nullopt);  // past int's range in time
  EXPECT_EQ(ParseIteration("12x"), std::nullopt);
  EXPECT_EQ(ParseIteration("-5"), std::nullopt);
}

// The smoke run with everything the symmetric config adds: mirror images of every sample, skill
// switches within episodes, constraints as terminations and standing starts.
TrainConfig SymmetricSmokeConfig() {
  TrainConfig config = SmokeConfig();
  config.symmetry.enabled = true;
  config.symmetry.self_paired_skills = 2;  // skills 0 and 1 mirror each other
  config.skill_switch.interval_s = {0.1, 0.2};
  config.skill_switch.reward_mask_steps = 3;
  config.env.constraints.enabled = true;
  config.env.reset.standing_fraction = 0.5;
  return config;
}

TEST_F(TrainingRun, SymmetricIterationsTrainOnMirrorImagesAndCheckpointTheConstraintScales) {
  const TrainConfig config = SymmetricSmokeConfig();
  testutil::SkillRun a(config);
  a.runner.RunIteration();
  const RunnerStats s = a.runner.RunIteration();
  const SkillDiscoveryStats& task_stats = a.task.stats();
  EXPECT_TRUE(s.finite);
  // A random policy slides its feet: some steps violate, and end with some probability.
  EXPECT_GT(task_stats.constraints.violation_rate[static_cast<int>(Constraint::kFootSlip)], 0.0);
  EXPECT_GT(task_stats.constraints.mean_probability, 0.0);
  EXPECT_LE(task_stats.constraints.mean_probability, 1.0);
  for (double rate : task_stats.constraints.violation_rate) EXPECT_TRUE(rate >= 0.0 && rate <= 1.0) << rate;
  a.runner.SaveCheckpoint(Path("sym.pt"));
  const std::string scales = ReadValue(Path("sym.pt"), "constraint_scales").toStringRef();
  EXPECT_NE(scales.find_first_not_of("0 "), std::string::npos) << scales;
  testutil::SkillRun b(config);
  b.runner.LoadCheckpoint(Path("sym.pt"));
  b.runner.SaveCheckpoint(Path("sym_again.pt"));
  EXPECT_EQ(ReadValue(Path("sym_again.pt"), "constraint_scales").toStringRef(), scales);
  // Its evaluation names each skill's mirror image.
  const Evaluation eval = EvaluateSkills(config, a.task.actor_critic(), a.runner.normalizer(), EvaluationOptions{false, 30, 1});
  EXPECT_EQ(eval.mirror_skill, (std::vector<int>{1, 0, 2, 3}));
  const nlohmann::json json = EvaluationJson(eval);
  EXPECT_EQ(json["skills"][1]["mirror_skill"], 0);
  ASSERT_EQ(json["mirror_pairs"].size(), 1u);
  EXPECT_EQ(json["mirror_pairs"][0]["skills"], (std::vector<int>{0, 1}));
  EXPECT_EQ(json["bar"]["num_skills"], 4);
}

// With discriminator.heading, q gains the heading turned since the skill began: the
// discriminator and the critic read one more input, and a checkpoint of one layout does not load
// into the other.
TEST_F(TrainingRun, TheHeadingTurnedIsAThirdCoordinateOfQ) {
  TrainConfig config = SymmetricSmokeConfig();
  config.discriminator.heading = true;
  testutil::SkillRun a(config);
  EXPECT_TRUE(a.runner.RunIteration().finite);
  EXPECT_TRUE(a.runner.RunIteration().finite);
  EXPECT_EQ(a.task.discriminator()->parameters().front().size(1), 3 + 2 * config.pae.latent_channels);
  EXPECT_EQ(a.task.actor_critic()->named_parameters()["critic.0.weight"].size(1), PolicyObservationSize(config.num_skills) + 3);
  a.runner.SaveCheckpoint(Path("heading.pt"));
  EXPECT_EQ(LoadTrainedPolicy(config, Path("heading.pt")).policy->named_parameters()["critic.0.weight"].size(1),
            PolicyObservationSize(config.num_skills) + 3);
  config.discriminator.heading = false;
  testutil::SkillRun b(config);
  EXPECT_THAT(InputErrorMessage([&] { b.runner.LoadCheckpoint(Path("heading.pt")); }), HasSubstr("does not fit"));
}

TEST(TrainingConfigs, EveryShippedSkillConfigLoads) {
  int loaded = 0;
  for (const auto& entry : fs::directory_iterator(ResolveDataPath("configs"))) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("flsd_", 0) != 0 || entry.path().extension() != ".yaml") continue;
    EXPECT_NO_THROW(LoadTrainConfig(entry.path().string())) << name;
    ++loaded;
  }
  EXPECT_GE(loaded, 4);
}

TEST(TrainingConfigs, TheServedConfigsEndEpisodesByTheSupervisorsDefaults) {
  const TerminationConfig supervisor = TerminationOf(SafetyConfig{});
  for (const TerminationConfig& served :
       {LoadTrainConfig(ResolveDataPath("configs/flsd_cpu_served.yaml")).env.termination,
        LoadTrainConfig(ResolveDataPath("configs/flsd_cpu_symmetric.yaml")).env.termination,
        LoadTrainConfig(ResolveDataPath("configs/flsd_cpu_symmetric_mild.yaml")).env.termination,
        LoadVelocityTrainConfig(ResolveDataPath("configs/selector_tracking_served.yaml")).env.termination}) {
    EXPECT_EQ(served.limits.max_tilt, supervisor.limits.max_tilt);
    EXPECT_EQ(served.limits.min_base_height, supervisor.limits.min_base_height);
    EXPECT_EQ(served.limits.max_joint_speed, supervisor.limits.max_joint_speed);
    EXPECT_EQ(served.limits.max_joint_speed_time, supervisor.limits.max_joint_speed_time);
    EXPECT_EQ(served.limits.joint_range_margin, supervisor.limits.joint_range_margin);
    EXPECT_EQ(served.on_calf_contact, supervisor.on_calf_contact);
  }
}

TEST_F(TrainingRun, SetChangesANewRunsRecordedConfigAndIsRefusedOnResume) {
  const std::atomic<bool> stop{false};
  TrainingRunOptions options;
  options.config_path = ResolveDataPath("configs/smoke.yaml");
  options.run_dir = dir_;
  options.iterations = 1;
  options.overrides = {"ppo.entropy_coef=0.004", "env.reset.standing_fraction=0.5"};
  ASSERT_EQ(RunTraining(options, stop), 0);
  const TrainConfig recorded = LoadTrainConfig(Path("config.yaml"));
  EXPECT_DOUBLE_EQ(recorded.ppo.entropy_coef, 0.004);
  EXPECT_DOUBLE_EQ(recorded.env.reset.standing_fraction, 0.5);
  EXPECT_EQ(recorded.num_envs, SmokeConfig().num_envs);

  options.resume = true;
  options.iterations = 2;
  EXPECT_THAT(InputErrorMessage([&] { RunTraining(options, stop); }),
              AllOf(HasSubstr("--set"), HasSubstr("a resumed run keeps its own")));
  options.overrides = {"ppo.entropy_coeff=0.1"};
  options.resume = false;
  const std::string other = dir_ + "_typo";
  options.run_dir = other;
  EXPECT_THAT(InputErrorMessage([&] { RunTraining(options, stop); }), HasSubstr("ppo.entropy_coeff: unknown key"));
  fs::remove_all(other);
}

TEST_F(TrainingRun, KeepsACheckpointEveryKeepIterationsThatEvalAndExportCanLoad) {
  const std::atomic<bool> stop{false};
  TrainingRunOptions options;
  options.config_path = ResolveDataPath("configs/smoke.yaml");  // keep_checkpoint_every: 3
  options.run_dir = dir_;
  options.iterations = 7;
  ASSERT_EQ(RunTraining(options, stop), 0);
  EXPECT_TRUE(fs::exists(KeptCheckpointPath(dir_, 3)));
  EXPECT_TRUE(fs::exists(KeptCheckpointPath(dir_, 6)));
  EXPECT_EQ(std::distance(fs::directory_iterator(Path("checkpoints")), fs::directory_iterator{}), 2);

  const nlohmann::json eval = EvaluateRun(dir_, EvaluationOptions{}, 3);
  EXPECT_EQ(eval["iteration"], 3);
  EXPECT_TRUE(fs::exists(Path("eval_3.json")));
  EXPECT_TRUE(fs::exists(Path("eval_3_skills.csv")));
  EXPECT_FALSE(fs::exists(Path("eval.json"))) << "the latest checkpoint's evaluation was overwritten";
  EvaluationOptions randomized;
  randomized.randomize = true;
  randomized.steps = 50;
  EXPECT_EQ(EvaluateRun(dir_, randomized, 3, 2)["starts_per_skill"], 2);
  EXPECT_TRUE(fs::exists(Path("eval_3_randomized_starts2.json")));
  EXPECT_TRUE(fs::exists(Path("eval_3_randomized_starts2_skills.csv")));
  EXPECT_EQ(ExportRun(dir_, Path("kept.safetensors"), 6)["iteration"], 6);
  EXPECT_EQ(ExportRun(dir_, Path("latest.safetensors"))["iteration"], 7);
  EXPECT_THAT(InputErrorMessage([&] { RunCheckpoint(dir_, 4); }),
              HasSubstr("kept no checkpoint of iteration 4 (kept: 3, 6)"));
}

TEST_F(TrainingRun, JudgesEachKeptCheckpointAsALibraryAndNamesTheBest) {
  const std::atomic<bool> stop{false};
  TrainingRunOptions options;
  options.config_path = ResolveDataPath("configs/smoke.yaml");
  options.run_dir = dir_;
  options.iterations = 4;
  options.overrides = {"keep_best=true", "keep_checkpoint_every=2", "env.episode_steps=40"};
  EXPECT_THAT(InputErrorMessage([&] { BestIteration(dir_); }), HasSubstr("has no best.json"));
  ASSERT_EQ(RunTraining(options, stop), 0);
  const nlohmann::json best = nlohmann::json::parse(std::ifstream(Path("best.json")));
  ASSERT_EQ(best["judged"].size(), 2u);
  EXPECT_EQ(best["judged"][0]["iteration"], 2);
  EXPECT_EQ(best["judged"][1]["iteration"], 4);
  const int chosen = best["iteration"].get<int>();
  EXPECT_EQ(BestIteration(dir_), chosen);
  // The best's bar is its evaluation over the export's randomised starts, and no other judged bar beats it.
  const std::string eval_file = "eval_" + std::to_string(chosen) + "_randomized_starts" + std::to_string(kRandomizedStarts) + ".json";
  const nlohmann::json eval = nlohmann::json::parse(std::ifstream(Path(eval_file)));
  EXPECT_EQ(best["bar"], eval["bar"]);
  const LibraryBar chosen_bar = LibraryBarFromJson(best["bar"], "best");
  for (const nlohmann::json& judged : best["judged"]) {
    EXPECT_FALSE(BetterLibrary(LibraryBarFromJson(judged["bar"], "judged"), chosen_bar)) << judged["iteration"];
  }
  // A resumed run that keeps more checkpoints judges them beside the others.
  options.resume = true;
  options.overrides.clear();
  options.iterations = 6;
  ASSERT_EQ(RunTraining(options, stop), 0);
  const nlohmann::json resumed = nlohmann::json::parse(std::ifstream(Path("best.json")));
  ASSERT_EQ(resumed["judged"].size(), 3u);
  EXPECT_EQ(resumed["judged"][2]["iteration"], 6);
}

TEST_F(TrainingRun, TravelPaysSkillsForGoingTheirWays) {
  const std::atomic<bool> stop{false};
  TrainingRunOptions options;
  options.config_path = ResolveDataPath("configs/smoke.yaml");
  options.run_dir = dir_;
  options.iterations = 1;
  options.overrides = {"travel.weight=1", "travel.directions=[forward, left, turn_left, none]"};
  ASSERT_EQ(RunTraining(options, stop), 0);
  const std::vector<std::string> lines = Lines(Path("progress.csv"));
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_THAT(lines[0], ::testing::EndsWith(",travel_reward"));
  EXPECT_NE(std::stod(lines[1].substr(lines[1].rfind(',') + 1)), 0.0);

  // Under symmetry, a pair of skills must go mirror-image ways.
  options.run_dir = dir_ + "_mirror";
  options.overrides = {"travel.weight=1", "symmetry.enabled=true", "symmetry.self_paired_skills=2",
                       "travel.directions=[left, left, forward, none]"};
  EXPECT_THAT(InputErrorMessage([&] { RunTraining(options, stop); }),
              AllOf(HasSubstr("travel.directions[1]"), HasSubstr("must go 'right'")));
  fs::remove_all(options.run_dir);
}

// The symmetric smoke config with its four skills paid for the four straight ways.
TrainConfig StraightTravelSmokeConfig() {
  TrainConfig config = SymmetricSmokeConfig();
  config.travel.weight = 1.0;
  config.travel.directions = {"left", "right", "forward", "backward"};
  return config;
}

// The task's statistics over the first rollout of `config`: changes to rewards and ends, not to
// the physics, compare on the same rollout.
SkillDiscoveryStats FirstRolloutStats(const TrainConfig& config) {
  testutil::SkillRun run(config);
  run.runner.RunIteration();
  return run.task.stats();
}

// travel.upright holds the travel skills to the base height at any speed: more steps violate it
// than when only a travelling or turning robot is held to it. Without constraints it has nothing to hold.
TEST_F(TrainingRun, UprightHoldsTravelSkillsToTheBaseHeightAtAnySpeed) {
  TrainConfig config = StraightTravelSmokeConfig();
  constexpr int kLowBase = static_cast<int>(Constraint::kLowBaseMoving);
  const double moving_only = FirstRolloutStats(config).constraints.violation_rate[kLowBase];
  config.travel.upright = true;
  EXPECT_GT(FirstRolloutStats(config).constraints.violation_rate[kLowBase], moving_only);

  config.travel.directions = {"still", "still", "none", "none"};
  EXPECT_THAT(InputErrorMessage([&] { ValidateTrainConfig(config, "test config"); }),
              AllOf(HasSubstr("travel.upright"), HasSubstr("holds no skill")));
  config.env.constraints.enabled = false;
  EXPECT_THAT(InputErrorMessage([&] { ValidateTrainConfig(config, "test config"); }),
              AllOf(HasSubstr("travel.upright"), HasSubstr("env.constraints.enabled")));
}

// travel.upright_still holds the still skills to the base height too: more steps violate it than
// with the movers alone held. It needs travel.upright.
TEST_F(TrainingRun, UprightStillHoldsTheStillSkillsToo) {
  TrainConfig config = StraightTravelSmokeConfig();
  config.travel.directions = {"still", "still", "forward", "backward"};
  config.travel.upright = true;
  constexpr int kLowBase = static_cast<int>(Constraint::kLowBaseMoving);
  const double movers_only = FirstRolloutStats(config).constraints.violation_rate[kLowBase];
  config.travel.upright_still = true;
  EXPECT_GT(FirstRolloutStats(config).constraints.violation_rate[kLowBase], movers_only);

  config.travel.upright = false;
  EXPECT_THAT(InputErrorMessage([&] { ValidateTrainConfig(config, "test config"); }),
              AllOf(HasSubstr("travel.upright_still"), HasSubstr("needs travel.upright: true")));
}

// travel.slip_tolerance discounts the pay of steps whose stance feet slide: the travel skills
// earn less on the same rollout, and not nothing.
TEST_F(TrainingRun, SlipToleranceDiscountsTheTravelPayOfSlidingSteps) {
  TrainConfig config = StraightTravelSmokeConfig();
  const double undiscounted = FirstRolloutStats(config).travel_reward;
  config.travel.slip_tolerance = 0.05;
  const double discounted = FirstRolloutStats(config).travel_reward;
  EXPECT_LT(discounted, undiscounted);
  EXPECT_GT(discounted, 0.0);

  config.env.constraints.enabled = false;
  EXPECT_THAT(InputErrorMessage([&] { ValidateTrainConfig(config, "test config"); }),
              AllOf(HasSubstr("travel.slip_tolerance"), HasSubstr("env.constraints.enabled")));
}

TEST_F(TrainingRun, EvaluatesAndExportsARun) {
  const std::atomic<bool> stop{false};
  TrainingRunOptions options;
  options.config_path = ResolveDataPath("configs/smoke.yaml");
  options.run_dir = dir_;
  options.iterations = 6;
  ASSERT_EQ(RunTraining(options, stop), 0);

  const nlohmann::json eval = EvaluateRun(dir_, EvaluationOptions{});
  std::ifstream eval_file(Path("eval.json"));
  ASSERT_TRUE(eval_file) << "no eval.json";
  const nlohmann::json written = nlohmann::json::parse(eval_file);
  EXPECT_EQ(written, eval);
  EXPECT_EQ(written["num_skills"], 4);
  EXPECT_EQ(written["iteration"], 6);
  EXPECT_EQ(written["state_coverage"]["cells_total"], 16384);
  EXPECT_EQ(written["skills"].size(), 4u);
  EXPECT_EQ(Lines(Path("eval_skills.csv")).size(), 1u + 4u);

  const std::string library_path = Path("skills.safetensors");
  const nlohmann::json summary = ExportRun(dir_, library_path);
  EXPECT_EQ(summary["num_skills"], 4);
  // Each descriptor's randomised slip is its skill's mean over the randomised evaluation's starts.
  const nlohmann::json exported = nlohmann::json::parse(ReadSafeTensors(library_path).metadata.at("flsd"));
  const nlohmann::json& randomized = exported["policies"][0]["randomized_evaluation"];
  EXPECT_EQ(randomized["starts_per_skill"], kRandomizedStarts);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(exported["skills"][k]["randomized_stance_foot_speed"], randomized["skills"][k]["mean_stance_foot_speed"]);
  }
  EXPECT_EQ(summary["iteration"], 6);
  const SafeTensors library = ReadSafeTensors(library_path);
  EXPECT_EQ(library.metadata.at("format"), "flsd-skill-library");
  const nlohmann::json meta = nlohmann::json::parse(library.metadata.at("flsd"));
  EXPECT_EQ(meta["format"], "flsd-skill-library");
  EXPECT_EQ(meta["num_skills"], 4);
  EXPECT_EQ(meta["joint_names"].get<std::vector<std::string>>(),
            std::vector<std::string>(a1::kJointNames.begin(), a1::kJointNames.end()));
  EXPECT_EQ(meta["action"]["scale"], 0.25);
  EXPECT_EQ(meta["control"]["kp"], 20.0);
  EXPECT_EQ(meta["control"]["kd"], 0.5);
  EXPECT_EQ(meta["control"]["control_dt"], 0.02);
  EXPECT_EQ(meta["observation"]["normalized_size"], 45);
  const nlohmann::json& policy = meta["policies"][0];  // the run's, the only one
  EXPECT_EQ(meta["policies"].size(), 1u);
  EXPECT_EQ(policy["observation_size"], 49);  // 33 + 12 + 4
  EXPECT_EQ(policy["training"]["iteration"], 6);
  EXPECT_EQ(policy["training"]["env_steps"], 6 * kStepsPerIteration);
  EXPECT_EQ(policy["training"]["method"], "flsd");
  EXPECT_EQ(policy["hidden"].get<std::vector<int>>(), (std::vector<int>{32, 32}));
  EXPECT_EQ(policy["activation"], "elu");
  EXPECT_EQ(meta["skills"].size(), 4u);
  const int layers = policy["layers"].get<int>();
  ASSERT_EQ(layers, 3);

  // Exactly the policy's layers and the normaliser, with the shapes of the smoke nets.
  const std::map<std::string, std::vector<int64_t>> shapes = {
      {"policies.0.layer0.weight", {32, 49}},  {"policies.0.layer0.bias", {32}},
      {"policies.0.layer1.weight", {32, 32}},  {"policies.0.layer1.bias", {32}},
      {"policies.0.layer2.weight", {12, 32}},  {"policies.0.layer2.bias", {12}},
      {"policies.0.normalizer.mean", {45}},    {"policies.0.normalizer.std", {45}}};
  ASSERT_EQ(library.tensors.size(), shapes.size());
  for (const auto& [name, shape] : shapes) {
    ASSERT_EQ(library.tensors.count(name), 1u) << name;
    EXPECT_EQ(library.tensors.at(name).shape, shape) << name;
  }

  // Inference parity with the trainer's own forward pass, on observations spread as the
  // normaliser saw them, one per skill.
  TrainedPolicy trained = LoadTrainedPolicy(LoadTrainConfig(Path("config.yaml")), Path("checkpoint.pt"));
  const FloatTensor& mean = library.tensors.at("policies.0.normalizer.mean");
  const FloatTensor& std = library.tensors.at("policies.0.normalizer.std");
  torch::manual_seed(11);
  for (int skill = 0; skill < 4; ++skill) {
    const torch::Tensor noise = torch::randn({45});
    std::vector<float> obs(49, 0.0f);
    for (int i = 0; i < 45; ++i) obs[i] = mean.values[i] + std.values[i] * noise[i].item<float>();
    obs[45 + skill] = 1.0f;
    const std::vector<double> by_hand = MeanActionByHand(library, layers, obs);
    torch::NoGradGuard no_grad;
    const torch::Tensor o = torch::from_blob(obs.data(), {1, 49}).clone();
    const torch::Tensor action = trained.policy->ActionMean(NormalizeLeadingColumns(trained.normalizer, o));
    ASSERT_EQ(action.sizes(), torch::IntArrayRef({1, kActionSize}));
    ASSERT_EQ(by_hand.size(), static_cast<size_t>(kActionSize));
    for (int j = 0; j < kActionSize; ++j) {
      EXPECT_NEAR(action[0][j].item<double>(), by_hand[j], 1e-5) << "skill " << skill << ", action " << j;
    }
  }
}

}  // namespace
}  // namespace flsd
