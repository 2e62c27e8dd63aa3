#include "skills/learning/evaluation/evaluation.h"

#include <filesystem>
#include <sstream>

#include "core/atomic_file.h"
#include "core/check.h"
#include "robot/observation.h"
#include "core/thread_pool.h"
#include "sim/vec_env.h"
#include "skills/learning/evaluation/library_bar.h"
#include "skills/learning/runners/run_loop.h"
#include "skills/learning/runners/trainer.h"

namespace flsd {
namespace {

TrajectoryPoint PointOf(const Env& env) {
  const RobotState& s = env.state();
  TrajectoryPoint p;
  p.stance_foot_speed = env.StanceFootSpeed();
  for (int k = 0; k < 3; ++k) {
    p.linear_velocity[k] = s.base_linear_velocity[k];
    p.angular_velocity[k] = s.base_angular_velocity[k];
  }
  p.base_height = s.base_position.z();
  p.position = {s.base_position.x(), s.base_position.y()};
  p.joint_position = s.joint_position;
  p.joint_velocity = s.joint_velocity;
  return p;
}

nlohmann::json Array(const double* v, int n) { return std::vector<double>(v, v + n); }

// What the velocity task's reward needs of one control step.
struct TaskStep {
  RobotState state;
  std::array<float, kActionSize> action;
  bool collision;
};

// legged_gym's velocity-task reward per second, term by term, that a skill earns when the command
// is its own mean velocity (VelocityRewardConfig: the A1's scales).
VelocityRewardTerms OwnVelocityTaskReward(const RobotState& start, const std::vector<TaskStep>& steps,
                                          const SkillSummary& skill) {
  VelocityRewardTerms mean{};
  if (steps.empty()) return mean;
  const VelocityRewardConfig config;
  VelocityTrackingReward reward(config);
  reward.Reset(start);
  const Eigen::Vector3d command(skill.mean_linear_velocity[0], skill.mean_linear_velocity[1],
                                skill.mean_angular_velocity[2]);
  const double n = static_cast<double>(steps.size());
  for (const TaskStep& step : steps) {
    const VelocityRewardTerms scaled = Scaled(reward.Step(step.state, command, step.action.data(), step.collision), config);
    ForEachTerm(mean, scaled, [&](const char*, double& sum, double term) { sum += term / n; });
    mean.total += scaled.total / n;
  }
  return mean;
}

nlohmann::json TermsJson(const VelocityRewardTerms& terms) {
  nlohmann::json json;
  ForEachTerm(terms, terms, [&](const char* name, double value, double) { json[name] = value; });
  json["total"] = terms.total;
  return json;
}

}  // namespace

Evaluation EvaluateSkills(const TrainConfig& config, ActorCritic policy, RunningNormalizer normalizer,
                          const EvaluationOptions& options) {
  torch::NoGradGuard no_grad;
  const int skills = config.num_skills;
  EnvConfig env = config.env;
  if (!options.randomize) {
    env.randomization.DisableAll();
    env.reset.base_velocity = 0.0;
    env.reset.joint_pos_scale = {1.0, 1.0};
  }
  const int steps = options.steps > 0 ? options.steps : env.episode_steps;
  // One step beyond the record, so no episode times out (and is reset) inside it: a VecEnv keeps
  // only the o^m of a final state, and the trajectory needs the whole RobotState.
  env.episode_steps = steps + 1;
  // One env per skill, stepped together; an env's record ends at its first termination.
  VecEnv vec(env, skills, options.seed, ResolveThreadCount(config.num_threads));

  Evaluation eval;
  eval.method = config.method;
  eval.steps = steps;
  eval.randomized = options.randomize;
  eval.trajectories.resize(skills);
  const mirror::SkillPairing pairing = SkillPairingOf(skills, config.symmetry);
  for (int k = 0; k < skills; ++k) eval.mirror_skill.push_back(pairing(k));
  std::vector<bool> running(skills, true);
  const int obs_size = PolicyObservationSize(skills);
  torch::Tensor raw = torch::zeros({skills, obs_size});
  std::vector<float> previous(skills * kActionSize, 0.0f);
  std::vector<RobotState> start(skills);
  std::vector<std::vector<TaskStep>> task_steps(skills);
  for (int k = 0; k < skills; ++k) {
    eval.trajectories[k].skill = k;
    eval.trajectories[k].points.reserve(steps);
    start[k] = vec.env(k).state();
  }
  for (int t = 0; t < steps; ++t) {
    for (int k = 0; k < skills; ++k) {
      BuildPolicyObservation(vec.motion_obs() + k * kMotionObsSize, &previous[k * kActionSize], k, skills,
                             raw.data_ptr<float>() + k * obs_size);
    }
    const torch::Tensor action = policy->ActionMean(NormalizeLeadingColumns(normalizer, raw)).contiguous();
    const float* a = action.data_ptr<float>();
    std::copy(a, a + skills * kActionSize, previous.begin());
    vec.Step(a);
    bool any = false;
    for (int k = 0; k < skills; ++k) {
      if (!running[k]) continue;
      const Termination ending = vec.termination()[k];
      // A failed state is not part of the skill (and the env has already been reset).
      if (ending == Termination::kNone) {
        eval.trajectories[k].points.push_back(PointOf(vec.env(k)));
        TaskStep& step = task_steps[k].emplace_back();
        step.state = vec.env(k).state();
        std::copy(a + k * kActionSize, a + (k + 1) * kActionSize, step.action.begin());
        step.collision = vec.stepped_calf_contact(k);
      }
      if (ending != Termination::kNone) {
        running[k] = false;
        eval.trajectories[k].fell = IsFailure(ending);
      }
      any |= running[k];
    }
    if (!any) break;
  }
  ComputeMetrics(eval, 1.0 / a1::kControlDt);
  for (int k = 0; k < skills; ++k) {
    eval.skills[k].task_reward_per_s = OwnVelocityTaskReward(start[k], task_steps[k], eval.skills[k]);
  }
  return eval;
}

Evaluation EvaluateWorstOfStarts(const TrainConfig& config, ActorCritic policy, RunningNormalizer normalizer,
                                 const EvaluationOptions& options, int starts) {
  FLSD_DEMAND(starts >= 1);
  Evaluation worst = EvaluateSkills(config, policy, normalizer, options);
  worst.starts = starts;
  for (int n = 1; n < starts; ++n) {
    EvaluationOptions other = options;
    other.seed = options.seed + static_cast<uint64_t>(n);
    const Evaluation e = EvaluateSkills(config, policy, normalizer, other);
    for (std::size_t k = 0; k < worst.skills.size(); ++k) {
      SkillSummary& s = worst.skills[k];
      s.survival_steps = std::min(s.survival_steps, e.skills[k].survival_steps);
      s.fell = s.fell || e.skills[k].fell;
    }
  }
  worst.survivors = 0;
  for (const SkillSummary& s : worst.skills) worst.survivors += Survives(s.survival_steps);
  return worst;
}

nlohmann::json EvaluationJson(const Evaluation& e) {
  nlohmann::json coverage_dims = nlohmann::json::array();
  for (int d = 0; d < kCoverageDims; ++d) {
    coverage_dims.push_back({{"name", kCoverageRanges[d].name},
                             {"max", e.coverage.max[d]},
                             {"min", e.coverage.min[d]},
                             {"coverage", e.coverage.dim_rate[d]}});
  }
  nlohmann::json skills = nlohmann::json::array();
  nlohmann::json pairs = nlohmann::json::array();
  for (const SkillSummary& s : e.skills) {
    const int image = s.skill < static_cast<int>(e.mirror_skill.size()) ? e.mirror_skill[s.skill] : s.skill;
    if (image > s.skill) {
      // A pair moves as mirror images when its yaw rates and lateral speeds are opposite: each
      // sum relative to the larger of the two is 0 for perfect mirror images, 1 for one still.
      const SkillSummary& m = e.skills[image];
      auto asymmetry = [](double a, double b) {
        const double scale = std::max(std::abs(a), std::abs(b));
        return scale > 1e-9 ? std::abs(a + b) / scale : 0.0;
      };
      pairs.push_back({{"skills", {s.skill, image}},
                       {"yaw_rate_asymmetry", asymmetry(s.mean_angular_velocity[2], m.mean_angular_velocity[2])},
                       {"lateral_asymmetry", asymmetry(s.mean_linear_velocity[1], m.mean_linear_velocity[1])}});
    }
    skills.push_back({{"skill", s.skill},
                      {"mirror_skill", image},
                      {"survival_steps", s.survival_steps},
                      {"fell", s.fell},
                      {"mean_linear_velocity", Array(s.mean_linear_velocity.data(), 3)},
                      {"mean_angular_velocity", Array(s.mean_angular_velocity.data(), 3)},
                      {"mean_base_height", s.mean_base_height},
                      {"gait_frequency_hz", s.gait_frequency_hz},
                      {"high_frequency_ratio", s.high_frequency_ratio},
                      {"mean_stance_foot_speed", s.mean_stance_foot_speed},
                      {"max_joint_speed", s.max_joint_speed},
                      {"longest_overspeed_s", s.longest_overspeed_s},
                      {"displacement", Array(s.displacement.data(), 2)},
                      {"task_reward_per_s", TermsJson(s.task_reward_per_s)}});
  }
  return {
      {"method", e.method},
      {"steps_per_skill", e.steps},
      {"randomized", e.randomized},
      {"starts_per_skill", e.starts},
      {"num_skills", e.skills.size()},
      {"skills_surviving_500_steps", e.survivors},
      {"state_coverage",
       {{"rate", e.coverage.rate},
        {"cells_visited", e.coverage.cells_visited},
        {"cells_total", e.coverage.cells_total},
        {"skills_counted", e.coverage.skills_counted},
        {"dimensions", coverage_dims}}},
      {"high_frequency_power_ratio",
       {{"cutoff_hz", 10.0},
        {"pooled", e.high_frequency.pooled_ratio},
        {"mean", e.high_frequency.mean_ratio},
        {"std", e.high_frequency.std_ratio}}},
      {"mirror_pairs", pairs},
      {"bar", LibraryBarJson(JudgeLibrary(e))},
      {"skills", skills},
  };
}

std::string SkillSummaryCsv(const Evaluation& e) {
  std::ostringstream out;
  out << "skill,survival_steps,fell,vx,vy,vz,wx,wy,wz,base_height,gait_frequency_hz,high_frequency_ratio,"
         "stance_foot_speed,max_joint_speed,longest_overspeed_s,dx,dy,task_tracking_per_s,task_reward_per_s\n";
  for (const SkillSummary& s : e.skills) {
    out << s.skill << ',' << s.survival_steps << ',' << s.fell;
    for (double v : s.mean_linear_velocity) out << ',' << v;
    for (double v : s.mean_angular_velocity) out << ',' << v;
    out << ',' << s.mean_base_height << ',' << s.gait_frequency_hz << ',' << s.high_frequency_ratio << ','
        << s.mean_stance_foot_speed << ',' << s.max_joint_speed << ',' << s.longest_overspeed_s << ','
        << s.displacement[0] << ',' << s.displacement[1] << ','
        << s.task_reward_per_s.tracking_lin_vel + s.task_reward_per_s.tracking_ang_vel << ','
        << s.task_reward_per_s.total << '\n';
  }
  return out.str();
}

nlohmann::json EvaluateRun(const std::string& run_dir, const EvaluationOptions& options, int iteration) {
  namespace fs = std::filesystem;
  const TrainConfig config = LoadTrainConfig((fs::path(run_dir) / "config.yaml").string());
  const TrainedPolicy trained = LoadTrainedPolicy(config, RunCheckpoint(run_dir, iteration));
  const Evaluation eval = EvaluateSkills(config, trained.policy, trained.normalizer, options);
  nlohmann::json json = EvaluationJson(eval);
  json["run"] = run_dir;
  json["iteration"] = trained.iteration;
  json["env_steps"] = trained.env_steps;
  const std::string suffix =
      (iteration > 0 ? "_" + std::to_string(iteration) : std::string()) + (options.randomize ? "_randomized" : "");
  WriteFileAtomically((fs::path(run_dir) / ("eval" + suffix + ".json")).string(), json.dump(2) + "\n");
  WriteFileAtomically((fs::path(run_dir) / ("eval" + suffix + "_skills.csv")).string(), SkillSummaryCsv(eval));
  return json;
}

}  // namespace flsd
