#include "skills/learning/algorithms/constraint_terminations.h"

#include <algorithm>
#include <sstream>

#include "core/check.h"

namespace flsd {

double ConstraintTerminations::MaxP(int constraint, int iteration) const {
  if (constraint == static_cast<int>(Constraint::kCalfContact)) return config_.calf_contact_max_p;
  const double max_p = config_.max_p.lo + RampProgress(iteration, 0) * (config_.max_p.hi - config_.max_p.lo);
  if (constraint != static_cast<int>(Constraint::kFootSlip)) return max_p;
  const double factor_progress = config_.foot_slip_start > 0 ? RampProgress(iteration, config_.foot_slip_start) : 1.0;
  const double factor = 1.0 + factor_progress * (config_.foot_slip_factor - 1.0);
  return std::min(1.0, factor * max_p);
}

double ConstraintTerminations::RampProgress(int iteration, int delay) const {
  if (config_.ramp_iterations <= 0) return iteration - first_iteration_ >= delay ? 1.0 : 0.0;
  return std::clamp(static_cast<double>(iteration - first_iteration_ - delay) / config_.ramp_iterations, 0.0, 1.0);
}

torch::Tensor ConstraintTerminations::Probabilities(const torch::Tensor& violations, int iteration,
                                                    const Communicator& comm, ConstraintStats& stats) {
  torch::NoGradGuard no_grad;
  if (first_iteration_ < 0) first_iteration_ = iteration;
  const torch::Tensor flat = violations.reshape({-1, kNumConstraints});
  const torch::Tensor local_max = std::get<0>(flat.max(0)).to(torch::kFloat64).contiguous();
  const std::vector<double> maxima =
      comm.Gather(std::vector<double>(local_max.data_ptr<double>(), local_max.data_ptr<double>() + kNumConstraints));
  const torch::Tensor rates = (flat > 0).to(torch::kFloat64).mean(0).contiguous();
  double summed[kNumConstraints + 1];
  std::copy(rates.data_ptr<double>(), rates.data_ptr<double>() + kNumConstraints, summed);

  std::vector<torch::Tensor> per_constraint;
  for (int c = 0; c < kNumConstraints; ++c) {
    double batch_max = 0.0;
    for (int r = 0; r < comm.size(); ++r) batch_max = std::max(batch_max, maxima[r * kNumConstraints + c]);
    scale_[c] = scale_[c] > 0.0 ? config_.ema_decay * scale_[c] + (1.0 - config_.ema_decay) * batch_max : batch_max;
    // In double: a constraint no longer violated has its scale decay by ema_decay every
    // iteration, below float's range within about 2000 of them, where 0 / scale would be NaN.
    const torch::Tensor v = flat.select(1, c).to(torch::kFloat64);
    per_constraint.push_back(scale_[c] > 0.0 ? MaxP(c, iteration) * (v / scale_[c]).clamp(0.0, 1.0)
                                             : torch::zeros_like(v));
  }
  const torch::Tensor probability = std::get<0>(torch::stack(per_constraint, 1).max(1));
  summed[kNumConstraints] = probability.mean().item<double>();
  comm.Sum(summed, kNumConstraints + 1);
  for (int c = 0; c < kNumConstraints; ++c) stats.violation_rate[c] = summed[c] / comm.size();
  stats.mean_probability = summed[kNumConstraints] / comm.size();
  return probability.reshape({violations.size(0), violations.size(1)}).to(violations.scalar_type());
}

std::string ConstraintTerminations::State() const {
  if (first_iteration_ < 0) return "";
  std::ostringstream out;
  out.precision(17);
  out << "first_iteration " << first_iteration_ << " scales";
  for (double s : scale_) out << ' ' << s;
  return out.str();
}

void ConstraintTerminations::Restore(const std::string& state, const std::string& where) {
  std::istringstream in(state);
  std::string word;
  // Checkpoints from before the ramp counted from the first constrained iteration hold the
  // scales alone, and those runs started with constraints at iteration 0.
  if (state.rfind("first_iteration", 0) == 0) {
    if (!(in >> word >> first_iteration_ >> word) || first_iteration_ < 0 || word != "scales") {
      throw InputError(where + ": constraint state: expected \"first_iteration <n> scales ...\", got \"" + state + "\"");
    }
  } else {
    first_iteration_ = 0;
  }
  for (double& s : scale_) {
    if (!(in >> s)) throw InputError(where + ": constraint scales: expected " + std::to_string(kNumConstraints) + " numbers");
  }
}

}  // namespace flsd
