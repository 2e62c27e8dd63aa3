#pragma once
// The paper's Section IV-C: PPO on legged_gym's velocity-tracking task, either as a skill
// selector (a categorical policy over the frozen skills of a library, FLSD-L and DIAYN-L of
// Fig. 8) or as a joint-level policy trained from scratch (Fig. 8's "Scratch"). Both run on the
// same VelocityTask, reward and PPO; only the action space differs.

#include <array>
#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "skills/learning/networks/actor_critic.h"
#include "skills/learning/runners/policy_learner.h"
#include "skills/learning/runners/progress_log.h"
#include "skills/learning/tasks/velocity_task.h"
#include "skills/runtime/nearest_skill.h"
#include "skills/runtime/skill_library.h"

namespace flsd {

enum class TaskMethod { kSelector, kScratch };
TaskMethod ParseTaskMethod(const std::string& name);  // "selector" or "scratch"

struct TaskTrainConfig {
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
  int iterations = 500;
  int checkpoint_every = 25;
  EnvConfig env;
  VelocityTaskConfig task;
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
    v("iterations", iterations, Bounds<int>{1, 100000000});
    v("checkpoint_every", checkpoint_every, Bounds<int>{1, 100000000});
    v("env", env);
    v("task", task);
    v("policy", policy);
    v("ppo", ppo);
  }
};

TaskTrainConfig LoadTaskTrainConfig(const std::string& path, const std::vector<std::string>& overrides = {});
void ValidateTaskTrainConfig(const TaskTrainConfig& config, const std::string& where);

// The observation the task policy sees: o^c for the selector (then its prior logits, one per
// skill, with a nearest-skill prior); o^c and the previous joint action for the scratch policy,
// whose action is the joint action itself. The leading NormalizedTaskObsSize columns are normalised.
int TaskPolicyObsSize(const TaskTrainConfig& config, int num_skills);
int NormalizedTaskObsSize(TaskMethod method);

struct TaskIterationStats {
  int iteration = 0;
  long env_steps = 0;
  double steps_per_s = 0.0;
  double mean_reward = 0.0;           // per control step, dt-scaled (legged_gym's units)
  double zero_reward_share = 0.0;     // of control steps paid exactly 0 (clipped): no gradient
  double mean_episode_return = 0.0;   // of the episodes that ended (0 if none did)
  int episodes_ended = 0;
  double mean_episode_length = 0.0;
  double fall_fraction = 0.0;
  double tracking_lin_vel = 0.0;      // mean of exp(-|cmd_xy - v_xy|^2 / sigma), 1 is perfect
  double tracking_ang_vel = 0.0;
  double lin_vel_error = 0.0;         // RMS of |cmd_xy - v_xy|, m/s
  double ang_vel_error = 0.0;         // RMS of |cmd_wz - w_z|, rad/s
  double entropy_or_std = 0.0;        // the selector's entropy, or the scratch policy's mean std
  double switches_per_s = 0.0;        // how often the selector changed skill within an episode
  PpoStats ppo;
  bool finite = true;
  double seconds_collect = 0.0, seconds_ppo = 0.0, seconds_total = 0.0;
};

ProgressRecord TaskProgress(const TaskIterationStats& stats);
std::string TaskProgressLine(const TaskIterationStats& stats, int total_iterations, double eta_seconds);

// The parts of a task checkpoint that run the selector: for export.
struct TrainedSelector {
  CategoricalActorCritic policy{nullptr};
  RunningNormalizer normalizer{nullptr};
  int iteration = 0;
  long env_steps = 0;
  std::string library_fingerprint;  // of the library it was trained over
};
TrainedSelector LoadTrainedSelector(const TaskTrainConfig& config, int num_skills, const std::string& checkpoint);

// With several ranks in `comm` (mpirun), config.num_envs is the whole job's, as for Trainer.
class TaskTrainer {
 public:
  explicit TaskTrainer(const TaskTrainConfig& config, const Communicator& comm = Communicator::Self());
  TaskTrainer(const TaskTrainer&) = delete;
  TaskTrainer& operator=(const TaskTrainer&) = delete;

  TaskIterationStats RunIteration();
  void SaveCheckpoint(const std::string& path) const;
  void LoadCheckpoint(const std::string& path);

  int iteration() const { return learner_.iteration(); }
  long env_steps() const { return learner_.env_steps(); }
  TaskMethod method() const { return method_; }
  std::shared_ptr<PpoPolicyImpl> policy() const { return policy_; }
  RunningNormalizer normalizer() const { return learner_.normalizer(); }
  const std::optional<SkillLibrary>& library() const { return library_; }

 private:
  void Collect(TaskIterationStats& stats);
  torch::Tensor Observations(bool update_normalizer);
  void JointActions(const torch::Tensor& policy_action);
  MirroredSamples MirroredRollout() const;
  // The nearest-skill prior of each row of commands [B, 3] (vx, vy, wz): [B, num_skills].
  torch::Tensor PriorLogits(const torch::Tensor& commands) const;

  TaskTrainConfig config_;
  const Communicator& comm_;
  TaskMethod method_;
  std::optional<SkillLibrary> library_;
  std::optional<NearestSkillSelector> nearest_;  // the prior's, with nearest_prior
  int num_envs_, steps_, obs_size_;
  VelocityTask task_;
  int streams_;  // reward streams: 1, or 2 (tracking, and the rest)
  ActorCritic scratch_{nullptr};
  CategoricalActorCritic selector_{nullptr};
  std::shared_ptr<PpoPolicyImpl> policy_;
  PolicyLearner learner_;
  Rollout& rollout_;  // the learner's

  std::vector<PolicyRunner> skill_runners_;  // per env: the frozen skills (selector)
  std::vector<float> previous_action_;       // per env: the last joint action, zero at a reset
  std::vector<float> joint_actions_;         // this step's, num_envs x 12
  std::vector<float> task_obs_;              // num_envs x kTaskObsSize
  std::vector<double> episode_return_;
  std::vector<int> episode_length_;
  std::vector<unsigned char> ended_;  // per env: its episode ended during this decision
  std::vector<int> last_choice_;      // per env: the selector's previous choice, -1 at an episode start

  torch::Tensor raw_obs_, last_values_;
  torch::Tensor raw_rollout_obs_;  // [T, N, obs] unnormalised, with mirror
  torch::Tensor commands_;          // [N, 3] this step's, with nearest_prior
  torch::Tensor rollout_commands_;  // [T, N, 3], with nearest_prior and mirror
};

// Per axis (vx, vy, wz), the range of the velocities of the library's surviving skills, with 0
// in it, times `widen`: the commands a selector over them can follow.
std::array<Interval, 3> CommandEnvelope(const SkillLibrary& library, double widen);

struct TaskRunOptions {
  std::string config_path;  // a new run's config; ignored on resume
  std::string method;       // overrides the config's, new runs only
  std::string library;      // overrides the config's, new runs only
  std::string run_dir;
  bool resume = false;
  int iterations = 0;
  int threads = 0;  // overrides the config's num_threads
  std::vector<std::string> overrides;  // a new run's "key.path=value" changes to its config
};
// As RunTraining (training_run.h), for the velocity task.
int RunTaskTraining(const TaskRunOptions& options, const std::atomic<bool>& stop_requested);

}  // namespace flsd
