// The target filter between a policy's action and the motors: its step response and its gain at a
// known frequency are those of a first-order low-pass filter, or of a second-order Butterworth
// filter, 0 Hz passes targets through, and a cutoff or order it cannot run is refused naming the
// range.

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

// The gain of a sine through `filter`, started at rest: the amplitude of the output's component
// at the sine's frequency over the last 5 s of 10 (a whole number of periods for these rates).
double MeasuredGain(TargetFilter filter, double hz) {
  filter.Reset(Filled(0.0));
  double in_phase = 0.0, quadrature = 0.0;
  for (int t = 0; t < 500; ++t) {
    const double phase = 2.0 * M_PI * hz * t * 0.02;
    const double y = filter.Apply(Filled(std::sin(phase)))[5];
    if (t < 250) continue;
    in_phase += y * std::sin(phase) / 125.0;
    quadrature += y * std::cos(phase) / 125.0;
  }
  return std::hypot(in_phase, quadrature);
}

TEST(TargetFilter, SecondOrderIsAButterworthFilterWithItsCutoffPrewarped) {
  // |H| = 1 / sqrt(1 + (tan(pi f dt) / tan(pi fc dt))^4): at 10 Hz, -3 dB at the cutoff, a 3 Hz
  // gait passes whole and a 20 Hz buzz keeps 5.6 % (the first order at 4 Hz: 80.5 % and 25.8 %).
  const TargetFilter filter(10.0, 2);
  for (const auto& [hz, expected] : {std::pair{3.0, 0.9976}, std::pair{10.0, 0.7071}, std::pair{20.0, 0.0556}}) {
    const double ratio = std::tan(M_PI * hz * 0.02) / std::tan(M_PI * 10.0 * 0.02);
    EXPECT_NEAR(1.0 / std::sqrt(1.0 + std::pow(ratio, 4)), expected, 1e-4) << hz << " Hz";
    EXPECT_NEAR(MeasuredGain(filter, hz), expected, 2e-3) << hz << " Hz";
  }
  EXPECT_NEAR(MeasuredGain(TargetFilter(4.0, 1), 3.0), 0.805, 2e-3);
}

TEST(TargetFilter, SecondOrderSettlesOnAStepWithoutDrift) {
  TargetFilter filter(10.0, 2);
  filter.Reset(Filled(-1.5));
  EXPECT_NEAR(filter.Apply(Filled(-1.5))[2], -1.5, 1e-12);  // at rest on its reset value
  double y = 0.0;
  for (int n = 0; n < 100; ++n) y = filter.Apply(Filled(0.5))[2];
  EXPECT_NEAR(y, 0.5, 1e-9);
}

TEST(TargetFilter, AnOrderOtherThanOneOrTwoIsRefused) {
  for (int bad : {0, 3}) {
    try {
      TargetFilter filter(10.0, bad);
      ADD_FAILURE() << "order " << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), ::testing::HasSubstr("expected 1 or 2")) << bad;
    }
  }
  EXPECT_THROW(TargetFilter(25.0, 2), InputError);  // the bilinear transform's pole at Nyquist
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
