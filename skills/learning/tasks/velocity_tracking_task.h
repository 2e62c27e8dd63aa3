#pragma once
// The paper's Section IV-C as a task for the on-policy runner: PPO on legged_gym's
// velocity-tracking environment, either as a skill selector (a categorical policy over the frozen
// skills of a library, FLSD-L and DIAYN-L of Fig. 8) or as a joint-level policy trained from
// scratch (Fig. 8's "Scratch"). Both run on the same VelocityCommandEnv, reward and PPO; only the
// action space differs.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "skills/learning/networks/actor_critic.h"
#include "skills/learning/runners/policy_learner.h"
#include "skills/learning/runners/rollout_task.h"
#include "skills/learning/tasks/selector_reward.h"
#include "skills/learning/tasks/velocity_command_env.h"
#include "skills/runtime/selector.h"
#include "skills/runtime/selector_memory.h"
#include "skills/runtime/skill_library.h"

namespace flsd {

enum class VelocityMethod { kSelector, kScratch };
VelocityMethod ParseVelocityMethod(const std::string& name);  // "selector" or "scratch"

struct VelocityTrainConfig {
  std::string method = "selector";
  std::string library;  // the skill library the selector chooses from (method selector)
  int seed = 1;
  int num_envs = 128;
  int num_threads = 0;
  int steps_per_env = 48;  // selector decisions (or scratch actions) per env per iteration
  // Control steps (20 ms) the selector holds each chosen skill: 1 is the paper's (a choice every
  // step); ETH D3's high level runs at 10 Hz, i.e. 5. The scratch policy acts every step.
  int decision_interval = 1;
  // Reward (x dt, like legged_gym's terms) per change of the chosen skill within an episode: not
  // the paper's. Without it the selector changes skill ~40 times a second and the switches drive
  // joints past the A1's speed limit. 0 turns it off.
  double switch_penalty = 0.0;
  // Train on every rollout's left-right mirror image too (robot/mirror.h): o^c mirrored, the
  // chosen skill's mirror image (the library's pairing) or the mirrored joint action.
  bool mirror = false;
  // legged_gym clips each step's reward at zero (only_positive_rewards); over skills whose
  // penalties exceed their tracking reward that leaves every step at zero and nothing to learn
  // from. With two streams the tracking terms and the rest (penalties, air time, the switch
  // penalty) each have a value head and advantages normalised on their own (ETH D3's multi-critic
  // PPO), unclipped; the logged reward stays legged_gym's clipped one, for comparison.
  bool reward_streams = false;
  int value_streams() const { return reward_streams ? 2 : 1; }
  // Not the paper's; 0 turns it off. The selector's logits are its network's plus the
  // nearest-skill prior at this temperature ((m/s)^2, NearestSkillSelector::Prior): it starts
  // as a soft nearest-skill selector and learns what to do better, instead of from a uniform
  // choice that switches the robot off its feet. The exported library records the temperature.
  double nearest_prior_temperature = 0.0;
  bool nearest_prior() const { return nearest_prior_temperature > 0.0; }
  // Not the paper's; 0 turns it off. Like the nearest-skill prior, but the logit of this value goes
  // to the time-sharing selector's choice (0 to the other choices): the selector starts as the
  // hand-made one serves and learns what to do better.
  double time_sharing_prior = 0.0;
  // A semi-MDP selector (selector_reward.h), with decision_interval its hold: on with a window.
  // The scratch policy can be paid the same reward (Fig. 8 on one task); it sees no memory.
  SelectorRewardConfig semi_mdp;
  // Discount per second of simulated time (0: ppo.gamma per decision, as given): PPO's gamma is
  // this to the power of one decision's seconds, so that the horizon does not change with the hold.
  double discount_per_second = 0.0;
  int iterations = 500;
  int checkpoint_every = 25;
  int keep_checkpoint_every = 0;  // a copy of the checkpoint every this many iterations (0: none)
  EnvConfig env;
  VelocityEnvConfig task;
  PolicyConfig policy;
  PpoConfig ppo;
  template <class V>
  void Visit(V& v) {
    v("method", method);
    v("library", library);
    v("seed", seed, Bounds<int>{0, 2147483647});
    v("num_envs", num_envs, Bounds<int>{1, 1000000});
    v("num_threads", num_threads, Bounds<int>{0, 1024});
    v("steps_per_env", steps_per_env, Bounds<int>{1, 100000});
    v("decision_interval", decision_interval, Bounds<int>{1, 1000});
    v("switch_penalty", switch_penalty, Bounds<double>{-1e3, 0.0});
    v("mirror", mirror);
    v("reward_streams", reward_streams);
    v("nearest_prior_temperature", nearest_prior_temperature, Bounds<double>{0.0, 1e3});
    v("time_sharing_prior", time_sharing_prior, Bounds<double>{0.0, 1e3});
    v("semi_mdp", semi_mdp);
    v("discount_per_second", discount_per_second, Bounds<double>{0.0, 1.0});
    v("iterations", iterations, Bounds<int>{1, 100000000});
    v("checkpoint_every", checkpoint_every, Bounds<int>{1, 100000000});
    v("keep_checkpoint_every", keep_checkpoint_every, Bounds<int>{0, 100000000});
    v("env", env);
    v("task", task);
    v("policy", policy);
    v("ppo", ppo);
  }
};

VelocityTrainConfig LoadVelocityTrainConfig(const std::string& path, const std::vector<std::string>& overrides = {});
void ValidateVelocityTrainConfig(const VelocityTrainConfig& config, const std::string& where);
// The PPO settings a run trains with: config.ppo, its gamma per decision from discount_per_second.
PpoConfig VelocityPpoConfig(const VelocityTrainConfig& config);

// The observation the task policy sees: for the selector, its network's input (SelectorNetwork:
// o^c, then a semi-MDP selector's memory) and then its prior logits (SelectorPrior: the masks and
// the prior, one per skill); o^c and the previous joint action for the scratch policy, whose
// action is the joint action itself. The leading NormalizedVelocityObsSize columns are normalised.
int VelocityPolicyObsSize(const VelocityTrainConfig& config, int num_skills);
int NormalizedVelocityObsSize(const VelocityTrainConfig& config);
// What a selector run's exported network is: its input, prior and hold as skilld runs them.
SelectorNetwork SelectorShape(const VelocityTrainConfig& config);

// The task's figures of one iteration, over every rank.
struct VelocityTrackingStats {
  // Per control step, dt-scaled: legged_gym's reward, or a semi-MDP selector's own.
  double mean_reward = 0.0;
  double zero_reward_share = 0.0;     // of control steps paid exactly 0 (clipped): no gradient
  double mean_episode_return = 0.0;   // of the episodes that ended (0 if none did)
  int episodes_ended = 0;
  double mean_episode_length = 0.0;
  double fall_fraction = 0.0;
  double tracking_lin_vel = 0.0;      // mean of exp(-|cmd_xy - v_xy|^2 / sigma), 1 is perfect
  double tracking_ang_vel = 0.0;
  double lin_vel_error = 0.0;         // RMS of |cmd_xy - v_xy|, m/s
  double ang_vel_error = 0.0;         // RMS of |cmd_wz - w_z|, rad/s
  double switches_per_s = 0.0;        // how often the selector changed skill within an episode
};

// A velocity-tracking run's progress.csv columns; `entropy_or_std` is the selector's entropy or the
// scratch policy's mean std.
ProgressRecord VelocityProgress(const RunnerStats& runner, const VelocityTrackingStats& task, double entropy_or_std);

// The parts of a selector run's checkpoint that run the selector: for export.
struct TrainedSelector {
  CategoricalActorCritic policy{nullptr};
  RunningNormalizer normalizer{nullptr};
  int iteration = 0;
  long env_steps = 0;
  std::string library_fingerprint;  // of the library it was trained over
};
TrainedSelector LoadTrainedSelector(const VelocityTrainConfig& config, int num_skills, const std::string& checkpoint);
// The parts of a scratch run's checkpoint that run its policy: for evaluation.
TrainedPolicy LoadTrainedScratch(const VelocityTrainConfig& config, const std::string& checkpoint);

// Per axis (vx, vy, wz), the range of the velocities of the library's surviving skills, with 0
// in it, times `widen`: the commands a selector over them can follow.
std::array<Interval, 3> CommandEnvelope(const SkillLibrary& library, double widen);

// With several ranks in `comm` (mpirun), config.num_envs is the whole job's: this rank steps its
// equal share.
class VelocityTrackingTask : public RolloutTask {
 public:
  // Checks the config and seeds libtorch's generator before any network draws its weights.
  explicit VelocityTrackingTask(const VelocityTrainConfig& config, const Communicator& comm = Communicator::Self());
  VelocityTrackingTask(const VelocityTrackingTask&) = delete;
  VelocityTrackingTask& operator=(const VelocityTrackingTask&) = delete;

  std::shared_ptr<PpoPolicyImpl> policy() const override { return policy_; }
  RolloutShape shape() const override;
  int normalized_obs() const override { return NormalizedVelocityObsSize(config_); }
  int control_steps_per_step() const override { return config_.decision_interval; }
  bool mirrored() const override { return config_.mirror; }

  void BeginRollout() override;
  void Observe(torch::Tensor& raw) override;
  void Step(int t, const torch::Tensor& actions, Rollout& rollout) override;
  void FinishRollout(Rollout& rollout, int iteration) override;
  MirroredSamples Mirror(const torch::Tensor& raw_obs, const Rollout& rollout,
                         const RunningNormalizer& normalizer) const override;

  std::vector<Rng>& env_streams() override { return env_.command_rngs(); }
  const char* env_streams_key() const override { return "command_rng"; }
  uint64_t env_streams_seed() const override { return config_.seed + VelocityCommandEnv::kCommandStream; }
  void Save(torch::serialize::OutputArchive& archive) const override;
  void Load(torch::serialize::InputArchive& archive, const std::string& path) override;

  ProgressRecord Progress(const RunnerStats& runner) const override;
  std::string ProgressLine(const RunnerStats& runner, int total_iterations, double eta_seconds) const override;

  VelocityMethod method() const { return method_; }
  const VelocityTrackingStats& stats() const { return stats_; }
  const std::optional<SkillLibrary>& library() const { return library_; }

 private:
  // The joint actions for this control step: the chosen skill's, or the scratch policy's own.
  void JointActions(const torch::Tensor& policy_action);
  // A semi-MDP selector's reward for env i's last control step, which ended as `ending`.
  double SemiMdpReward(int i, Termination ending) const;
  // The selector's entropy, or the scratch policy's mean std, after PPO's update.
  double EntropyOrStd(const RunnerStats& runner) const;

  VelocityTrainConfig config_;
  const Communicator& comm_;
  VelocityMethod method_;
  std::optional<SkillLibrary> library_;
  SelectorNetwork shape_;  // the selector's input, prior and hold (not its weights)
  int num_envs_, steps_, obs_size_;
  VelocityCommandEnv env_;
  int streams_;  // reward streams: 1, or 2 (tracking, and the rest)
  ActorCritic scratch_{nullptr};
  CategoricalActorCritic selector_{nullptr};
  std::shared_ptr<PpoPolicyImpl> policy_;
  VelocityTrackingStats stats_;

  std::vector<PolicyRunner> skill_runners_;  // per env: the frozen skills (selector)
  std::vector<SelectorPrior> priors_;        // per env: the masks and prior, as skilld's (selector)
  std::vector<SelectorMemory> memories_;     // per env: the running skill and a semi-MDP selector's memory
  // For the mirrored samples (mirror); without a time-sharing prior, Write changes nothing.
  mutable std::optional<SelectorPrior> mirror_prior_;
  std::vector<float> previous_action_;       // per env: the last joint action, zero at a reset
  std::vector<float> joint_actions_;         // this step's, num_envs x 12
  std::vector<float> task_obs_;              // num_envs x kTaskObsSize
  std::vector<double> episode_return_;
  std::vector<int> episode_length_;
  std::vector<unsigned char> ended_;  // per env: its episode ended during this decision
  std::vector<int> last_choice_;      // per env: the selector's previous choice, -1 at an episode start

  // This rollout's sums over this rank's control steps (FinishRollout reduces them).
  struct Sums {
    long ended = 0, length_sum = 0, falls = 0, switches = 0;
    long zero_rewards = 0;  // steps the clip at zero left without any gradient
    double return_sum = 0.0, reward_sum = 0.0, lin_sum = 0.0, ang_sum = 0.0, lin_err2 = 0.0, ang_err2 = 0.0;
  } sums_;

  // With mirror: each decision's command [T, N, 3], and the skill before the running one and the
  // running one [T, N, 2] (-1: none).
  torch::Tensor rollout_commands_, rollout_skills_;
};

}  // namespace flsd
