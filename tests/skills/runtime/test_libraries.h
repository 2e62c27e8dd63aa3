#pragma once
// Small skill libraries written by the learning side's export, for the runtime's tests: random
// weights, non-trivial normaliser statistics, and evaluations with known values.

#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "robot/observation.h"
#include "skills/learning/export/export.h"
#include "skills/runtime/safetensors.h"
#include "tests/common/test_support.h"

namespace flsd::testutil {

// `skills` skills, symmetric: with 5, pairs (0, 2) and (1, 3), and skill 4 its own mirror image.
inline TrainConfig SmallLibraryConfig(int skills = 5) {
  TrainConfig config;
  config.num_skills = skills;
  config.policy.actor_hidden = {32, 16};
  config.policy.critic_hidden = {8};
  config.symmetry.enabled = true;
  config.symmetry.self_paired_skills = skills % 2;
  return config;
}

inline TrainedPolicy RandomPolicy(const TrainConfig& config, uint64_t seed = 3) {
  torch::manual_seed(seed);
  TrainedPolicy p;
  const int obs = PolicyObservationSize(config.num_skills);
  p.policy = ActorCritic(obs, obs + 2, kActionSize, config.policy);
  p.normalizer = RunningNormalizer(kMotionObsSize + kActionSize);
  p.normalizer->Update(torch::randn({64, kMotionObsSize + kActionSize}) * 3.0 + 1.0);
  p.iteration = 7;
  p.env_steps = 700;
  return p;
}

// Skill k survives 1000 - k steps and walks at 0.1 k m/s forward.
inline Evaluation FakeEvaluation(int skills) {
  Evaluation e;
  e.method = "flsd";
  for (int k = 0; k < skills; ++k) {
    SkillSummary s;
    s.skill = k;
    s.survival_steps = 1000 - k;
    s.mean_linear_velocity = {0.1 * k, -0.2, 0.0};
    s.mean_base_height = 0.25;
    s.gait_frequency_hz = 2.0;
    s.mean_stance_foot_speed = 0.01 * k;
    e.skills.push_back(s);
  }
  return e;
}

// The same skills under the training randomisation: shorter lives, the last one falling.
inline Evaluation FakeRandomizedEvaluation(int skills) {
  Evaluation e = FakeEvaluation(skills);
  e.randomized = true;
  for (SkillSummary& s : e.skills) {
    s.survival_steps = 400 - s.skill;
    s.mean_stance_foot_speed = 0.02 * s.skill;  // rough floors slide the feet more
  }
  e.skills.back().fell = true;
  return e;
}

inline void WriteTestLibrary(const std::string& path, const TrainConfig& config, const TrainedPolicy& policy) {
  WriteSkillLibrary(path, config, policy, FakeEvaluation(config.num_skills), FakeRandomizedEvaluation(config.num_skills),
                    ExportProvenance{"run", "abc", "def"});
}

// The library at `from` as format version 1 wrote it: one policy described at /policy, /training
// and /evaluation, its tensors named policy.layer<l>.* and normalizer.*, no policy in the skills.
inline void WriteAsVersion1(const std::string& from, const std::string& to) {
  const SafeTensors v2 = ReadSafeTensors(from);
  nlohmann::json meta = nlohmann::json::parse(v2.metadata.at("flsd"));
  nlohmann::json policy = meta["policies"][0];
  meta.erase("policies");
  meta["format_version"] = 1;
  for (const char* key : {"training", "evaluation", "randomized_evaluation"}) {
    meta[key] = policy[key];
    policy.erase(key);
  }
  const int skills = policy["num_skills"];
  for (const char* key : {"num_skills", "observation_size"}) policy.erase(key);
  meta["policy"] = policy;
  meta["observation"]["policy"]["skill_onehot"] = skills;
  meta["observation"]["policy_size"] = PolicyObservationSize(skills);
  for (nlohmann::json& skill : meta["skills"]) {
    skill.erase("policy");
    skill.erase("policy_skill");
  }
  SafeTensors v1;
  v1.metadata = v2.metadata;
  v1.metadata["flsd"] = meta.dump();
  const std::string prefix = "policies.0.";
  for (const auto& [name, tensor] : v2.tensors) {
    const std::string rest = name.substr(prefix.size());
    v1.tensors[rest.rfind("normalizer.", 0) == 0 ? rest : "policy." + rest] = tensor;
  }
  WriteSafeTensors(to, v1);
}

struct Velocity {
  double vx, vy, wz;
};

// A library whose skill k moves at velocities[k]; skills in `fallen` fell in the randomised
// evaluation.
inline std::string WriteLibrary(const std::vector<Velocity>& velocities, const std::vector<int>& fallen) {
  TrainConfig config;
  config.num_skills = static_cast<int>(velocities.size());
  config.policy.actor_hidden = {8};
  config.policy.critic_hidden = {8};
  TrainedPolicy policy;
  const int obs = PolicyObservationSize(config.num_skills);
  policy.policy = ActorCritic(obs, obs + 2, kActionSize, config.policy);
  policy.normalizer = RunningNormalizer(kMotionObsSize + kActionSize);
  Evaluation nominal, randomized;
  for (int k = 0; k < config.num_skills; ++k) {
    SkillSummary s;
    s.skill = k;
    s.survival_steps = 1000;
    s.mean_linear_velocity = {velocities[k].vx, velocities[k].vy, 0.0};
    s.mean_angular_velocity = {0.0, 0.0, velocities[k].wz};
    nominal.skills.push_back(s);
    s.fell = std::find(fallen.begin(), fallen.end(), k) != fallen.end();
    randomized.skills.push_back(s);
  }
  const std::string path = testutil::UniqueTempPath("nearest.safetensors");
  WriteSkillLibrary(path, config, policy, nominal, randomized, ExportProvenance{"run", "abc", "def"});
  return path;
}

// The same, recording a fall on each switch (from, to) in `falls` (flsd transitions --record) and
// on each cycle of `cycle_falls` (flsd cycles --record).
inline std::string WriteLibraryWithFallingSwitches(const std::vector<Velocity>& velocities,
                                            const std::vector<std::pair<int, int>>& falls,
                                            const std::vector<std::vector<int>>& cycle_falls = {}) {
  const std::string path = WriteLibrary(velocities, {});
  SafeTensors file = ReadSafeTensors(path);
  nlohmann::json meta = nlohmann::json::parse(file.metadata["flsd"]);
  meta["transitions"]["falls"] = falls;
  if (!cycle_falls.empty()) meta["cycles"]["falls"] = cycle_falls;
  file.metadata["flsd"] = meta.dump();
  WriteSafeTensors(path, file);
  return path;
}

}  // namespace flsd::testutil
