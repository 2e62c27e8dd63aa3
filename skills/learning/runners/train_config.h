#pragma once
// Everything a training run is configured by, read from one YAML file (configs/flsd_*.yaml).

#include <string>

#include "core/config.h"
#include "sim/env_config.h"
#include "skills/learning/networks/actor_critic.h"
#include "skills/learning/algorithms/constraint_terminations.h"
#include "skills/learning/algorithms/symmetry.h"
#include "skills/learning/networks/discriminator.h"
#include "skills/learning/networks/pae.h"
#include "skills/learning/algorithms/ppo.h"
#include "skills/learning/tasks/travel_reward.h"

namespace flsd {

// What the discriminator sees: FLSD's phase manifold (Eq. 13) or DIAYN's raw motion state.
enum class Method { kFlsd, kDiayn };
Method ParseMethod(const std::string& name);  // "flsd" or "diayn"; throws InputError otherwise
const char* ToString(Method m);

// Smoothness penalties added to the intrinsic reward, legged_gym's terms and units (each scale x
// term x dt; legged_gym's reward scales). The paper uses none; without them the skills found on two
// cores chatter (actions flipping sign every 20 ms, feet tapping at ~19 Hz), which a downstream
// task's own smoothness terms then punish. ETH D3 adds such regularisation penalties to its
// skill discovery too. Zero turns a term off.
struct RegularizationConfig {
  double action_rate = 0.0;  // x |a_t - a_{t-1}|^2 (legged_gym: -0.01)
  double dof_acc = 0.0;      // x |(qdot_t - qdot_{t-1}) / dt|^2 (legged_gym: -2.5e-7)
  template <class V>
  void Visit(V& v) {
    v("action_rate", action_rate, Bounds<double>{-1e3, 0.0});
    v("dof_acc", dof_acc, Bounds<double>{-1e3, 0.0});
  }
  bool enabled() const { return action_rate != 0.0 || dof_acc != 0.0; }
};

// Skills resampled within an episode, as ETH D3 does, so that starting from another skill's motion
// is in the training distribution: the selector and navigation switch skills all the time.
struct SkillSwitchConfig {
  Interval interval_s{0.0, 0.0};  // s between draws, uniform in the interval; 0: one skill an episode
  // Steps after a switch whose reward is withheld and whose samples the discriminator does not
  // see: their motion window still holds the previous skill's motion (H/2 by default).
  int reward_mask_steps = 25;
  template <class V>
  void Visit(V& v) {
    v("interval_s", interval_s, Bounds<double>{0.0, 3600.0});
    v("reward_mask_steps", reward_mask_steps, Bounds<int>{0, 100000});
  }
  bool enabled() const { return interval_s.hi > 0.0; }
};

struct TrainConfig {
  std::string method = "flsd";
  int seed = 1;
  int num_envs = 64;
  int num_threads = 0;  // 0: every core
  int steps_per_env = 48;
  int iterations = 1000;
  int num_skills = 16;  // N_k
  int window = 51;      // H: 1 s of motion at 50 Hz
  // legged_gym's only_positive_rewards: a negative reward would make falling early attractive.
  bool only_positive_rewards = true;
  // legged_gym multiplies every reward by the control period (0.02 s), which keeps returns of
  // order one; rsl_rl's value clipping (0.2 per update) assumes that scale.
  double reward_scale = 0.02;
  double critic_position_scale = 0.25;  // the critic also sees q_xy, x this (1/m)
  int checkpoint_every = 25;            // iterations
  // Iterations between checkpoints kept for good as checkpoints/ITER.pt (0: none). A run's skills
  // can peak mid-run and be lost by the end (runs/flsd_replicate_s1 had 8 movers at 1250, 4 at 3009).
  int keep_checkpoint_every = 250;
  // Judge each kept checkpoint as a library and name the best in best.json (JudgeKeptCheckpoint).
  bool keep_best = true;
  RegularizationConfig regularization;
  SymmetryConfig symmetry;
  SkillSwitchConfig skill_switch;
  // How likely env.constraints' violations end an episode (when env.constraints.enabled).
  ConstraintTerminationConfig constraint_terminations;
  EnvConfig env;
  PolicyConfig policy;
  PpoConfig ppo;
  PaeConfig pae;
  DiscriminatorConfig discriminator;
  TravelConfig travel;  // off by default: the paper's reward alone

  template <class V>
  void Visit(V& v) {
    v("method", method);
    v("seed", seed, Bounds<int>{0, 2147483647});
    v("num_envs", num_envs, Bounds<int>{1, 1000000});
    v("num_threads", num_threads, Bounds<int>{0, 1024});
    v("steps_per_env", steps_per_env, Bounds<int>{1, 100000});
    v("iterations", iterations, Bounds<int>{1, 100000000});
    v("num_skills", num_skills, Bounds<int>{2, 10000});
    v("window", window, Bounds<int>{3, 1001});
    v("only_positive_rewards", only_positive_rewards);
    v("reward_scale", reward_scale, Bounds<double>{1e-6, 1e6});
    v("critic_position_scale", critic_position_scale, Bounds<double>{0.0, 100.0});
    v("checkpoint_every", checkpoint_every, Bounds<int>{1, 100000000});
    v("keep_checkpoint_every", keep_checkpoint_every, Bounds<int>{0, 100000000});
    v("keep_best", keep_best);
    v("regularization", regularization);
    v("symmetry", symmetry);
    v("skill_switch", skill_switch);
    v("constraint_terminations", constraint_terminations);
    v("env", env);
    v("policy", policy);
    v("ppo", ppo);
    v("pae", pae);
    v("discriminator", discriminator);
    v("travel", travel);
  }
};

// Reads and checks a whole training config file (unknown keys and bad values are errors).
TrainConfig LoadTrainConfig(const std::string& path, const std::vector<std::string>& overrides = {});
// The same checks for a config built in code or parsed from a checkpoint.
void ValidateTrainConfig(const TrainConfig& config, const std::string& where);

}  // namespace flsd
