#include "skills/learning/runners/policy_learner.h"

#include <string>

#include "core/check.h"
#include "core/rng.h"
#include "skills/learning/runners/checkpoint_io.h"

namespace flsd {

int LocalEnvCount(int total, const Communicator& comm) {
  if (total % comm.size() != 0) {
    throw InputError("num_envs " + std::to_string(total) + " does not divide among " + std::to_string(comm.size()) +
                     " ranks: give a multiple of the rank count");
  }
  return total / comm.size();
}

void SeedRankStreams(uint64_t seed, const Communicator& comm) {
  if (comm.rank() > 0) torch::manual_seed(StreamSeed(seed, comm.rank()));
}

PolicyLearner::PolicyLearner(std::shared_ptr<PpoPolicyImpl> policy, int normalized_obs, const PpoConfig& config,
                             uint64_t seed, const Communicator& comm)
    : policy_(std::move(policy)),
      normalizer_(normalized_obs),
      config_(config),
      seed_(seed),
      comm_(comm),
      ppo_(policy_, config, comm) {}

void PolicyLearner::AllocateRollout(const RolloutShape& s) {
  const auto f = torch::kFloat32;
  const int64_t t = s.steps, n = s.envs;
  rollout_.obs = torch::zeros({t, n, s.obs}, f);
  rollout_.critic_obs = s.critic_obs == s.obs ? rollout_.obs : torch::zeros({t, n, s.critic_obs}, f);
  rollout_.actions = torch::zeros({t, n, s.action}, f);
  rollout_.distributions = torch::zeros({t, n, s.distribution}, f);
  rollout_.log_probs = torch::zeros({t, n}, f);
  rollout_.values = s.value_streams > 1 ? torch::zeros({t, n, s.value_streams}, f) : torch::zeros({t, n}, f);
  rollout_.rewards = torch::zeros_like(rollout_.values);
  rollout_.dones = torch::zeros({t, n}, f);
  rollout_.timeouts = torch::zeros({t, n}, f);
}

void PolicyLearner::UpdateNormalizer(const torch::Tensor& raw) { flsd::UpdateNormalizer(normalizer_, raw, comm_); }

PpoStats PolicyLearner::Update(const torch::Tensor& last_values, const MirroredSamples* mirrored) {
  const Returns returns = ComputeReturns(rollout_, last_values, config_.gamma, config_.lambda, comm_);
  return ppo_.Update(rollout_, returns, mirrored);
}

void PolicyLearner::CountIteration(long job_steps) {
  ++iteration_;
  env_steps_ += job_steps;
}

void PolicyLearner::Write(torch::serialize::OutputArchive& archive, const std::vector<Rng>& env_streams,
                          const char* key) const {
  WriteModule(archive, "policy", *policy_);
  WriteModule(archive, "normalizer", *normalizer_);
  WriteOptimizer(archive, "policy_optimizer", ppo_.optimizer());
  archive.write("iteration", c10::IValue(static_cast<int64_t>(iteration_)));
  archive.write("env_steps", c10::IValue(static_cast<int64_t>(env_steps_)));
  archive.write("learning_rate", c10::IValue(ppo_.learning_rate()));
  archive.write("ranks", c10::IValue(static_cast<int64_t>(comm_.size())));
  WriteTorchRng(archive);
  archive.write(key, c10::IValue(RngState(env_streams)));
}

void PolicyLearner::Read(torch::serialize::InputArchive& archive, std::vector<Rng>& env_streams, const char* key,
                         uint64_t streams_seed, int first_env) {
  ReadPolicyParts(archive, *policy_, *normalizer_, iteration_, env_steps_);
  ReadOptimizer(archive, "policy_optimizer", ppo_.optimizer());
  ppo_.set_learning_rate(ReadDouble(archive, "learning_rate"));
  c10::IValue ranks(static_cast<int64_t>(1));  // checkpoints from before data parallelism
  archive.try_read("ranks", ranks);
  if (comm_.size() == 1 && ranks.toInt() == 1) {
    ReadTorchRng(archive);
    RestoreRngState(ReadString(archive, key), env_streams, key);
    return;
  }
  // The saved state is the leader's alone: every rank draws afresh for this layout.
  torch::manual_seed(StreamSeed(StreamSeed(seed_, comm_.rank()), iteration_));
  for (size_t i = 0; i < env_streams.size(); ++i) {
    env_streams[i].seed(StreamSeed(StreamSeed(streams_seed, first_env + i), iteration_));
  }
}

void ReadPolicyParts(torch::serialize::InputArchive& archive, torch::nn::Module& policy, torch::nn::Module& normalizer,
                     int& iteration, long& env_steps) {
  ReadModule(archive, "policy", policy);
  ReadModule(archive, "normalizer", normalizer);
  iteration = static_cast<int>(ReadInt(archive, "iteration"));
  env_steps = static_cast<long>(ReadInt(archive, "env_steps"));
}

}  // namespace flsd
