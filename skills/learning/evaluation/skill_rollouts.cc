#include "skills/learning/evaluation/skill_rollouts.h"

#include <algorithm>
#include <sstream>

#include "core/check.h"
#include "skills/learning/evaluation/library_bar.h"

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

nlohmann::json TermsJson(const VelocityRewardTerms& terms) {
  nlohmann::json json;
  ForEachTerm(terms, terms, [&](const char* name, double value, double) { json[name] = value; });
  json["total"] = terms.total;
  return json;
}

}  // namespace

EnvConfig EvaluationEnvConfig(const EnvConfig& training, const EvaluationOptions& options) {
  EnvConfig env = training;
  if (!options.randomize) env.randomization.DisableAll();
  if (!options.randomize || options.standing_start) {
    env.reset.base_velocity = 0.0;
    env.reset.joint_pos_scale = {1.0, 1.0};
  }
  // One step beyond the record, so no episode times out (and is reset) inside it: a VecEnv keeps
  // only the o^m of a final state, and the trajectory needs the whole RobotState.
  env.episode_steps = EvaluationSteps(training, options) + 1;
  return env;
}

int EvaluationSteps(const EnvConfig& training, const EvaluationOptions& options) {
  return options.steps > 0 ? options.steps : training.episode_steps;
}

SkillRollouts::SkillRollouts(int skills, int steps)
    : steps_(steps), trajectories_(skills), start_(skills), task_steps_(skills), running_(skills, true) {
  for (int k = 0; k < skills; ++k) {
    trajectories_[k].skill = k;
    trajectories_[k].points.reserve(steps);
  }
}

void SkillRollouts::Start(int skill, const RobotState& state) { start_[skill] = state; }

bool SkillRollouts::Record(int skill, const Env& env, Termination ending, const float* action, bool calf_contact) {
  if (!running_[skill]) return false;
  if (ending == Termination::kNone) {
    trajectories_[skill].points.push_back(PointOf(env));
    TaskStep& step = task_steps_[skill].emplace_back();
    step.state = env.state();
    std::copy(action, action + kActionSize, step.action.begin());
    step.calf_contact = calf_contact;
    return true;
  }
  running_[skill] = false;
  trajectories_[skill].fell = IsFailure(ending);
  return false;
}

Evaluation SkillRollouts::Finish(const std::string& method, bool randomized, std::vector<int> mirror_skill) const {
  Evaluation eval;
  eval.method = method;
  eval.steps = steps_;
  eval.randomized = randomized;
  eval.trajectories = trajectories_;
  eval.mirror_skill = std::move(mirror_skill);
  ComputeMetrics(eval, 1.0 / a1::kControlDt);
  for (std::size_t k = 0; k < eval.skills.size(); ++k) eval.skills[k].task_reward_per_s = TaskReward(k, eval.skills[k]);
  return eval;
}

VelocityRewardTerms SkillRollouts::TaskReward(std::size_t k, const SkillSummary& skill) const {
  const std::vector<TaskStep>& steps = task_steps_[k];
  VelocityRewardTerms mean{};
  if (steps.empty()) return mean;
  const VelocityRewardConfig config;
  VelocityTrackingReward reward(config);
  reward.Reset(start_[k]);
  const Eigen::Vector3d command(skill.mean_linear_velocity[0], skill.mean_linear_velocity[1],
                                skill.mean_angular_velocity[2]);
  const double n = static_cast<double>(steps.size());
  for (const TaskStep& step : steps) {
    const VelocityRewardTerms scaled = Scaled(reward.Step(step.state, command, step.action.data(), step.calf_contact), config);
    ForEachTerm(mean, scaled, [&](const char*, double& sum, double term) { sum += term / n; });
    mean.total += scaled.total / n;
  }
  return mean;
}

Evaluation EvaluateOverStarts(const EvaluationOptions& options, int starts,
                              const std::function<Evaluation(const EvaluationOptions&)>& evaluate) {
  FLSD_DEMAND(starts >= 1);
  Evaluation first = evaluate(options);
  first.starts = starts;
  for (int n = 1; n < starts; ++n) {
    EvaluationOptions other = options;
    other.seed = options.seed + static_cast<uint64_t>(n);
    const Evaluation e = evaluate(other);
    for (std::size_t k = 0; k < first.skills.size(); ++k) {
      SkillSummary& s = first.skills[k];
      s.survival_steps = std::min(s.survival_steps, e.skills[k].survival_steps);
      s.fell = s.fell || e.skills[k].fell;
      s.mean_stance_foot_speed += e.skills[k].mean_stance_foot_speed;
    }
  }
  first.survivors = 0;
  for (SkillSummary& s : first.skills) {
    s.mean_stance_foot_speed /= starts;
    first.survivors += Survives(s.survival_steps);
  }
  return first;
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

}  // namespace flsd
