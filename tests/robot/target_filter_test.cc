// The target filter between a policy's action and the motors: its step response and its gain at a
// known frequency are those of a first-order low-pass filter, 0 Hz passes targets through, and a
// cutoff it cannot run is refused naming the range.

#include "robot/target_filter.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "core/check.h"

namespace flsd {
namespace {

a1::JointArray<double> Filled(double value) {
  a1::JointArray<double> a;
  a.fill(value);
  return a;
}

TEST(TargetFilter, ZeroHertzPassesTargetsThrough) {
  TargetFilter filter(0.0);
  filter.Reset(Filled(0.0));
  EXPECT_EQ(filter.Apply(Filled(1.25))[7], 1.25);
}

TEST(TargetFilter, AStepIsFollowedExponentiallyWithTheCutoffsTimeConstant) {
  // 4 Hz at 50 Hz: each step covers 1 - exp(-2 pi 4 0.02) = 39.5 % of what is left.
  TargetFilter filter(4.0);
  filter.Reset(Filled(0.0));
  const double gain = 1.0 - std::exp(-2.0 * M_PI * 4.0 * 0.02);
  EXPECT_NEAR(gain, 0.3951, 1e-4);
  for (int n = 1; n <= 10; ++n) {
    const double y = filter.Apply(Filled(1.0))[0];
    EXPECT_NEAR(y, 1.0 - std::pow(1.0 - gain, n), 1e-12) << "step " << n;
  }
}

TEST(TargetFilter, A20HzTargetIsAttenuatedAsTheTransferFunctionSays) {
  // H(z) = g / (1 - (1 - g) z^-1) at 20 Hz, sampled at 50 Hz: |H| = 0.258 for a 4 Hz cutoff; the
  // buzz the filter is there for loses three quarters of its amplitude, a 1 Hz gait 3 %.
  const double g = 1.0 - std::exp(-2.0 * M_PI * 4.0 * 0.02);
  for (const auto& [hz, expected] : {std::pair{20.0, 0.258}, std::pair{1.0, 0.971}}) {
    const std::complex<double> z_inv = std::polar(1.0, -2.0 * M_PI * hz * 0.02);
    EXPECT_NEAR(std::abs(g / (1.0 - (1.0 - g) * z_inv)), expected, 1e-3) << hz << " Hz";
    TargetFilter filter(4.0);
    filter.Reset(Filled(0.0));
    double peak = 0.0;
    for (int t = 0; t < 500; ++t) {  // 10 s; the last 5 s are past the transient
      const double y = filter.Apply(Filled(std::sin(2.0 * M_PI * hz * t * 0.02 + 0.3)))[3];
      if (t >= 250) peak = std::max(peak, std::abs(y));
    }
    EXPECT_NEAR(peak, expected, 0.03) << hz << " Hz";
  }
}

TEST(TargetFilter, ACutoffOutsideZeroToNyquistIsRefused) {
  for (double bad : {-1.0, 25.5, std::nan("")}) {
    try {
      TargetFilter filter(bad);
      ADD_FAILURE() << bad << " Hz was accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr("expected 0 (off) to 25")) << bad;
    }
  }
}

}  // namespace
}  // namespace flsd
