// Constraints as terminations: a violation's probability is max_p times its share of the running
// scale of the largest violation, the step's is the largest over the constraints, the soft
// constraints' max_p ramps over the curriculum while a knee strike's stays, and the running
// scales survive a checkpoint.

#include "skills/learning/algorithms/constraint_terminations.h"

#include <gtest/gtest.h>

#include "core/check.h"

namespace flsd {
namespace {

constexpr int kSlip = static_cast<int>(Constraint::kFootSlip);
constexpr int kCalf = static_cast<int>(Constraint::kCalfContact);
constexpr int kSpeed = static_cast<int>(Constraint::kJointSpeed);

// [T = 1, N = 4, C]: env 0 slips 0.4 m/s past the limit, env 1 0.1, env 2 strikes a knee, env 3
// keeps every constraint.
torch::Tensor Violations() {
  torch::Tensor v = torch::zeros({1, 4, kNumConstraints});
  v[0][0][kSlip] = 0.4f;
  v[0][1][kSlip] = 0.1f;
  v[0][2][kCalf] = 1.0f;
  v[0][2][kSpeed] = 2.0f;
  return v;
}

TEST(ConstraintTerminations, ProbabilityIsMaxPTimesTheViolationOverItsRunningScale) {
  ConstraintTerminations cat(ConstraintTerminationConfig{});
  ConstraintStats stats;
  // Iteration 0: max_p 0.05 for soft constraints; the first batch sets the scales (0.4, 2, 1).
  const torch::Tensor p = cat.Probabilities(Violations(), 0, Communicator::Self(), stats);
  ASSERT_EQ(p.sizes(), (std::vector<int64_t>{1, 4}));
  EXPECT_NEAR(p[0][0].item<double>(), 0.05, 1e-7);
  EXPECT_NEAR(p[0][1].item<double>(), 0.05 * 0.1 / 0.4, 1e-7);
  EXPECT_NEAR(p[0][2].item<double>(), 1.0, 1e-7);  // the knee strike, not the soft overspeed
  EXPECT_EQ(p[0][3].item<double>(), 0.0);
  EXPECT_DOUBLE_EQ(stats.violation_rate[kSlip], 0.5);
  EXPECT_DOUBLE_EQ(stats.violation_rate[kCalf], 0.25);
  EXPECT_NEAR(stats.mean_probability, (0.05 + 0.0125 + 1.0) / 4, 1e-7);
  // Half way through the ramp max_p is 0.15, and the slip scale has moved 5 % toward 0.1:
  // 0.95 * 0.4 + 0.05 * 0.1 = 0.385.
  torch::Tensor smaller = torch::zeros({1, 4, kNumConstraints});
  smaller[0][0][kSlip] = 0.1f;
  const torch::Tensor q = cat.Probabilities(smaller, 500, Communicator::Self(), stats);
  EXPECT_NEAR(q[0][0].item<double>(), 0.15 * 0.1 / 0.385, 1e-6);
  // Past the ramp, a violation beyond the scale is capped at max_p (0.25).
  EXPECT_NEAR(cat.Probabilities(Violations() * 10.0, 5000, Communicator::Self(), stats)[0][0].item<double>(), 0.25,
              1e-6);
}

// A constraint violated once and then kept for 3000 iterations has its scale decay past float's
// range (0.95^3000 of it); a step that keeps it must still get probability 0, not NaN, and one
// that breaks it again the soft max_p. (A DIAYN run stopped on NaN rewards at iteration 2403.)
TEST(ConstraintTerminations, AScaleDecayedPastFloatsRangeGivesFiniteProbabilities) {
  ConstraintTerminations cat(ConstraintTerminationConfig{});
  ConstraintStats stats;
  cat.Probabilities(Violations(), 0, Communicator::Self(), stats);
  for (int i = 1; i <= 3000; ++i) cat.Probabilities(torch::zeros({1, 4, kNumConstraints}), i, Communicator::Self(), stats);
  const torch::Tensor kept = cat.Probabilities(torch::zeros({1, 4, kNumConstraints}), 3001, Communicator::Self(), stats);
  EXPECT_TRUE(torch::isfinite(kept).all().item<bool>());
  EXPECT_EQ(kept.max().item<double>(), 0.0);
  torch::Tensor again = torch::zeros({1, 4, kNumConstraints});
  again[0][0][kSlip] = 1e-3f;
  const torch::Tensor p = cat.Probabilities(again, 3002, Communicator::Self(), stats);
  EXPECT_EQ(p.scalar_type(), torch::kFloat32);
  EXPECT_NEAR(p[0][0].item<double>(), ConstraintTerminationConfig{}.max_p.hi, 1e-6);
  EXPECT_EQ(p[0][1].item<double>(), 0.0);
}

TEST(ConstraintTerminations, TheRunningScalesRoundTripThroughACheckpointString) {
  ConstraintTerminations cat(ConstraintTerminationConfig{}), restored(ConstraintTerminationConfig{});
  ConstraintStats stats;
  cat.Probabilities(Violations(), 0, Communicator::Self(), stats);
  restored.Restore(cat.State(), "checkpoint.pt");
  torch::Tensor next = torch::zeros({1, 4, kNumConstraints});
  next[0][1][kSlip] = 0.2f;
  EXPECT_TRUE(torch::equal(cat.Probabilities(next, 100, Communicator::Self(), stats),
                           restored.Probabilities(next, 100, Communicator::Self(), stats)));
  try {
    restored.Restore("first_iteration 0 scales 0.1 0.2", "checkpoint.pt");
    ADD_FAILURE() << "two scales were accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "checkpoint.pt: constraint scales: expected 5 numbers");
  }
}

TEST(ConstraintTerminations, TheRampCountsFromTheFirstConstrainedIteration) {
  // A run fine-tuned at iteration 4000 from an unconstrained checkpoint starts at max_p 0.05, is
  // half way (0.15) 500 iterations later, and keeps its start through a checkpoint.
  ConstraintTerminations cat(ConstraintTerminationConfig{}), restored(ConstraintTerminationConfig{});
  ConstraintStats stats;
  EXPECT_NEAR(cat.Probabilities(Violations(), 4000, Communicator::Self(), stats)[0][0].item<double>(), 0.05, 1e-7);
  restored.Restore(cat.State(), "checkpoint.pt");
  EXPECT_NEAR(restored.Probabilities(Violations(), 4500, Communicator::Self(), stats)[0][0].item<double>(), 0.15,
              1e-6);
  // A checkpoint of the scales alone (written before the start was saved) ramped from iteration 0.
  ConstraintTerminations legacy(ConstraintTerminationConfig{});
  legacy.Restore("0.4 0.1 0.1 2 1", "checkpoint.pt");
  EXPECT_NEAR(legacy.Probabilities(Violations(), 500, Communicator::Self(), stats)[0][0].item<double>(), 0.15, 1e-6);
}

TEST(ConstraintTerminations, TheSlipFactorScalesOnlyTheSlipsMaxPAndCapsItAtOne) {
  ConstraintTerminationConfig config;
  config.max_p = {0.01, 0.1};
  config.foot_slip_factor = 4.0;
  ConstraintTerminations cat(config);
  ConstraintStats stats;
  torch::Tensor v = Violations();
  v[0][3][kSpeed] = 1.0f;  // env 3 overspeeds at half the scale (2)
  const torch::Tensor p = cat.Probabilities(v, 0, Communicator::Self(), stats);
  EXPECT_NEAR(p[0][0].item<double>(), 0.04, 1e-7);               // slip at its scale: 4 x 0.01
  EXPECT_NEAR(p[0][1].item<double>(), 0.04 * 0.1 / 0.4, 1e-7);  // a quarter of the scale
  EXPECT_NEAR(p[0][3].item<double>(), 0.01 * 0.5, 1e-7);         // joint speed keeps max_p
  config.foot_slip_factor = 20.0;  // 20 x 0.01 at the ramp's start, 20 x 0.1 (capped at 1) at its end
  ConstraintTerminations capped(config);
  EXPECT_NEAR(capped.Probabilities(Violations(), 0, Communicator::Self(), stats)[0][0].item<double>(), 0.2, 1e-7);
  EXPECT_NEAR(capped.Probabilities(Violations(), 1000, Communicator::Self(), stats)[0][0].item<double>(), 1.0, 1e-7);
}

TEST(ConstraintTerminations, ADelayedSlipFactorRampsInFromOneAfterItsStart) {
  ConstraintTerminationConfig config;
  config.max_p = {0.01, 0.01};
  config.ramp_iterations = 100;
  config.foot_slip_factor = 5.0;
  config.foot_slip_start = 1000;
  ConstraintTerminations cat(config);
  ConstraintStats stats;
  const auto slip_p = [&](int iteration) {
    return cat.Probabilities(Violations(), iteration, Communicator::Self(), stats)[0][0].item<double>();
  };
  EXPECT_NEAR(slip_p(200), 0.01, 1e-7);   // the first constrained iteration: the factor is 1
  EXPECT_NEAR(slip_p(1200), 0.01, 1e-7);  // 1000 after it, the factor's ramp starts
  EXPECT_NEAR(slip_p(1250), 0.03, 1e-7);  // halfway: 1 + 0.5 x 4
  EXPECT_NEAR(slip_p(1300), 0.05, 1e-7);
  EXPECT_NEAR(slip_p(9000), 0.05, 1e-7);
}

}  // namespace
}  // namespace flsd
