// Data-parallel training, run by ctest under `mpirun -np 2`: ranks that each take their share of a
// fixed batch make the same update as one process taking all of it (PPO, the PAE, the
// discriminator), the normaliser's statistics merge exactly, and the ranks of a skill-discovery run
// and of a selector run keep identical parameters. Every rank runs every collective before it asserts anything, so that a failing
// check cannot leave the other rank waiting.

#include <gtest/gtest.h>

#include <vector>

#include "core/check.h"
#include "core/paths.h"
#include "skills/learning/runners/communicator.h"
#include "skills/learning/networks/discriminator.h"
#include "skills/learning/networks/normalizer.h"
#include "skills/learning/networks/pae.h"
#include "skills/learning/algorithms/ppo.h"
#include "tests/common/in_memory_run.h"

namespace flsd {
namespace {

const Communicator& World() { return Communicator::World(); }
const Communicator& Self() { return Communicator::Self(); }

// This rank's share of x along `dim`.
torch::Tensor Share(const torch::Tensor& x, int64_t dim) { return x.chunk(World().size(), dim)[World().rank()]; }

double MaxDifference(const std::vector<torch::Tensor>& a, const std::vector<torch::Tensor>& b) {
  double worst = 0.0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, (a[i] - b[i]).abs().max().item<double>());
  return worst;
}

class Distributed : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_GE(World().size(), 2) << "run this test under mpirun -np 2"; }
};

TEST_F(Distributed, CollectivesCombineEveryRank) {
  const int n = World().size(), rank = World().rank();
  const double sum = World().Sum(rank + 1.0);
  const bool any_second = World().Any(rank == 1), any_none = World().Any(false);
  const std::vector<double> gathered = World().Gather({double(rank), 10.0 * rank});
  EXPECT_DOUBLE_EQ(sum, n * (n + 1) / 2.0);
  EXPECT_TRUE(any_second);
  EXPECT_FALSE(any_none);
  ASSERT_EQ(gathered.size(), 2u * n);
  for (int r = 0; r < n; ++r) {
    EXPECT_EQ(gathered[2 * r], r);
    EXPECT_EQ(gathered[2 * r + 1], 10.0 * r);
  }
  const Communicator::Tally tally = World().TakeTally();
  EXPECT_EQ(tally.calls, 4);  // Sum, two Any, Gather
  EXPECT_EQ(tally.bytes, long(3 * sizeof(double) + 2 * sizeof(double)));
  EXPECT_EQ(World().TakeTally().calls, 0);
}

TEST_F(Distributed, PpoOnSharesOfABatchUpdatesAsOneProcessOnAllOfIt) {
  constexpr int kSteps = 5, kEnvs = 8, kObs = 6, kActions = 2;
  PolicyConfig policy_config;
  policy_config.actor_hidden = {16};
  policy_config.critic_hidden = {16};
  torch::manual_seed(7);
  ActorCritic whole(kObs, kObs, kActions, policy_config);
  torch::manual_seed(7);
  ActorCritic parted(kObs, kObs, kActions, policy_config);

  // The same batch on every rank, from the same seed.
  torch::manual_seed(11);
  Rollout batch;
  batch.obs = torch::randn({kSteps, kEnvs, kObs});
  batch.critic_obs = batch.obs;
  batch.actions = torch::randn({kSteps, kEnvs, kActions});
  {
    torch::NoGradGuard no_grad;
    batch.distributions = whole->Distribution(batch.obs);
    batch.log_probs = whole->LogProb(batch.distributions, batch.actions);
    batch.values = whole->Value(batch.critic_obs);
  }
  batch.rewards = torch::randn({kSteps, kEnvs});
  batch.dones = (torch::rand({kSteps, kEnvs}) < 0.2).to(torch::kFloat32);
  batch.timeouts = torch::zeros({kSteps, kEnvs});
  const torch::Tensor last_values = torch::randn({kEnvs});

  // Whole minibatches, so that the order of the samples within one does not matter.
  PpoConfig config;
  config.epochs = 3;
  config.minibatches = 1;
  std::vector<torch::Tensor> initial;
  for (const torch::Tensor& p : whole->parameters()) initial.push_back(p.detach().clone());
  Ppo reference(whole.ptr(), config, Self());
  const PpoStats expected = reference.Update(batch, ComputeReturns(batch, last_values, 0.99, 0.95, Self()));

  Rollout share;
  for (auto [from, to] : {std::pair{&batch.obs, &share.obs}, {&batch.critic_obs, &share.critic_obs},
                          {&batch.actions, &share.actions}, {&batch.distributions, &share.distributions},
                          {&batch.log_probs, &share.log_probs}, {&batch.values, &share.values},
                          {&batch.rewards, &share.rewards}, {&batch.dones, &share.dones},
                          {&batch.timeouts, &share.timeouts}}) {
    *to = Share(*from, 1);
  }
  Ppo parallel(parted.ptr(), config, World());
  const PpoStats got = parallel.Update(share, ComputeReturns(share, Share(last_values, 0), 0.99, 0.95, World()));

  EXPECT_LT(MaxDifference(parted->parameters(), whole->parameters()), 1e-5);
  EXPECT_DOUBLE_EQ(got.learning_rate, expected.learning_rate);
  EXPECT_NEAR(got.kl, expected.kl, 1e-6);
  EXPECT_NEAR(got.value_loss, expected.value_loss, 1e-5);
  EXPECT_GT(MaxDifference(whole->parameters(), initial), 1e-4);  // the update did something
}

TEST_F(Distributed, AdvantagesAreNormalisedOverEveryRanksBatch) {
  torch::manual_seed(3);
  Rollout batch;
  batch.rewards = torch::randn({4, 6});
  batch.values = torch::randn({4, 6});
  batch.dones = torch::zeros({4, 6});
  batch.timeouts = torch::zeros({4, 6});
  const torch::Tensor last = torch::randn({6});
  const Returns whole = ComputeReturns(batch, last, 0.99, 0.95, Self());
  Rollout share = batch;
  for (torch::Tensor* x : {&share.rewards, &share.values, &share.dones, &share.timeouts}) *x = Share(*x, 1);
  const Returns parted = ComputeReturns(share, Share(last, 0), 0.99, 0.95, World());
  EXPECT_LT((parted.advantages - Share(whole.advantages, 1)).abs().max().item<double>(), 1e-5);
  EXPECT_LT((parted.returns - Share(whole.returns, 1)).abs().max().item<double>(), 1e-5);
}

TEST_F(Distributed, PaeAndDiscriminatorOnSharesUpdateAsOneProcess) {
  constexpr int kBatch = 16, kWindow = 25, kChannels = 6, kSkills = 4;
  PaeConfig pae_config;
  pae_config.latent_channels = 3;
  pae_config.hidden_channels = 5;
  pae_config.kernel_size = 9;
  DiscriminatorConfig discriminator_config;
  discriminator_config.hidden = {16};
  torch::manual_seed(5);
  const torch::Tensor windows = torch::randn({kBatch, kChannels, kWindow});
  const torch::Tensor observations = torch::randn({kBatch, 8});
  const torch::Tensor skills = torch::randint(kSkills, {kBatch}, torch::kLong);

  struct Learner {
    PeriodicAutoencoder pae{nullptr};
    Discriminator discriminator{nullptr};
    double pae_loss = 0.0, discriminator_loss = 0.0;
  };
  auto train = [&](const Communicator& comm, const torch::Tensor& w, const torch::Tensor& o, const torch::Tensor& k) {
    torch::manual_seed(9);
    Learner l{PeriodicAutoencoder(kChannels, kWindow, 50.0, pae_config),
              Discriminator(8, kSkills, discriminator_config)};
    // Plain SGD: Adam's step is +-lr wherever a gradient is nearly zero, whatever its size, so it
    // would turn float rounding in the summation order into differences of the learning rate.
    torch::optim::SGD pae_optimizer(l.pae->parameters(), torch::optim::SGDOptions(1e-2));
    torch::optim::SGD discriminator_optimizer(l.discriminator->parameters(), torch::optim::SGDOptions(1e-1));
    const torch::Tensor rows = torch::arange(w.size(0), torch::kLong);
    // A minibatch of the whole batch: each rank's share of it is all of its rows.
    l.pae_loss = TrainEpochs(pae_optimizer, comm, rows, 3, kBatch, [&](const torch::Tensor& idx) {
      const torch::Tensor x = w.index_select(0, idx);
      return l.pae->Loss(x, l.pae->Forward(x));
    });
    l.discriminator_loss = TrainEpochs(discriminator_optimizer, comm, rows, 3, kBatch, [&](const torch::Tensor& idx) {
      return DiscriminatorLoss(l.discriminator->LogProbs(o.index_select(0, idx)), k.index_select(0, idx));
    });
    return l;
  };
  const Learner whole = train(Self(), windows, observations, skills);
  const Learner parted = train(World(), Share(windows, 0), Share(observations, 0), Share(skills, 0));

  EXPECT_LT(MaxDifference(parted.pae->parameters(), whole.pae->parameters()), 1e-5);
  EXPECT_LT(MaxDifference(parted.discriminator->parameters(), whole.discriminator->parameters()), 1e-5);
  // The reported loss is the mean over the ranks of their losses, which with whole minibatches
  // of equal shares is the whole batch's loss in each step.
  EXPECT_NEAR(parted.discriminator_loss, whole.discriminator_loss, 1e-5);
}

TEST_F(Distributed, NormaliserStatisticsMergeExactly) {
  torch::manual_seed(13);
  RunningNormalizer whole(5), parted(5);
  for (int i = 0; i < 3; ++i) {
    const torch::Tensor batch = torch::randn({12, 5}) * (i + 1) + i;
    whole->Update(batch);
    UpdateNormalizer(parted, Share(batch, 0), World());
  }
  EXPECT_DOUBLE_EQ(parted->count(), whole->count());
  EXPECT_LT((parted->mean() - whole->mean()).abs().max().item<double>(), 1e-12);
  EXPECT_LT((parted->variance() - whole->variance()).abs().max().item<double>(), 1e-12);
}

TEST_F(Distributed, SkillDiscoveryRanksKeepIdenticalParametersAndCountTheWholeJob) {
  TrainConfig config = LoadTrainConfig(ResolveDataPath("configs/smoke.yaml"));
  config.num_threads = 1;
  testutil::SkillRun run(config, World());
  RunnerStats stats;
  for (int i = 0; i < 2; ++i) stats = run.runner.RunIteration();
  double checksum = run.runner.normalizer()->mean().sum().item<double>();
  for (const auto& module : std::vector<std::shared_ptr<torch::nn::Module>>{
           run.task.actor_critic().ptr(), run.task.pae().ptr(), run.task.discriminator().ptr()}) {
    for (const torch::Tensor& p : module->parameters()) checksum += p.to(torch::kFloat64).abs().sum().item<double>();
  }
  const std::vector<double> checksums = World().Gather({checksum});
  for (double c : checksums) EXPECT_NEAR(c, checksums[0], 1e-9 * std::abs(checksums[0])) << "parameters diverged";
  EXPECT_EQ(stats.env_steps, 2L * config.num_envs * config.steps_per_env);
  EXPECT_GT(stats.collectives.calls, 0);
  EXPECT_EQ(run.task.vec_env().num_envs(), config.num_envs / World().size());
}

TEST_F(Distributed, SelectorRanksKeepIdenticalParametersAndCountTheWholeJob) {
  VelocityTrainConfig config = LoadVelocityTrainConfig(ResolveDataPath("configs/selector_smoke.yaml"));
  config.library = ResolveDataPath(config.library);
  const SkillLibrary library = SkillLibrary::Load(config.library);  // its skills run behind their own filter
  config.env.action_filter_hz = library.action_filter_hz();
  config.env.action_filter_order = library.action_filter_order();
  config.mirror = true;
  testutil::VelocityRun run(config, World());
  RunnerStats stats;
  for (int i = 0; i < 2; ++i) stats = run.runner.RunIteration();
  double checksum = run.runner.normalizer()->mean().sum().item<double>();
  for (const torch::Tensor& p : run.task.policy()->parameters()) {
    checksum += p.to(torch::kFloat64).abs().sum().item<double>();
  }
  const std::vector<double> checksums = World().Gather({checksum});
  for (double c : checksums) EXPECT_NEAR(c, checksums[0], 1e-9 * std::abs(checksums[0])) << "parameters diverged";
  EXPECT_EQ(stats.env_steps, 2L * config.num_envs * config.steps_per_env * config.decision_interval);
  // Every rank reports the job's figures: the same on each.
  const std::vector<double> rewards = World().Gather({run.task.stats().mean_reward});
  for (double r : rewards) EXPECT_EQ(r, rewards[0]);
}

TEST_F(Distributed, EnvCountThatDoesNotDivideIsAnInputError) {
  TrainConfig config = LoadTrainConfig(ResolveDataPath("configs/smoke.yaml"));
  config.num_envs = 2 * World().size() + 1;
  try {
    SkillDiscoveryTask task(config, World());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("does not divide among"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace flsd
