#include "skills/learning/networks/pae.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cmath>
#include <string>
#include <vector>

#include "skills/learning/networks/motion_streams.h"
#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;
using testutil::InputErrorMessage;

constexpr int kWindow = 51;      // H
constexpr double kRate = 50.0;   // Hz
constexpr int kChannels = 33;    // o^m

// The frequency of DFT bin k of an H-sample window.
double Bin(int k) { return k * kRate / kWindow; }

// a sin(2 pi f t + phi) + b at t_i = i / 50, i < H.
torch::Tensor Sinusoid(double a, double f, double phi, double b) {
  const torch::Tensor t = torch::arange(kWindow, torch::kFloat64) / kRate;
  return a * torch::sin(2.0 * M_PI * f * t + phi) + b;
}

void ExpectRelative(double actual, double expected, double tolerance, const std::string& what) {
  EXPECT_NEAR(actual, expected, tolerance * std::abs(expected)) << what;
}

struct Curve {
  double a, f, phi, b;
};

// Eq. 6 on single bin-aligned sinusoids: F is the bin frequency, A the amplitude, B the offset.
TEST(ComputeFourierParameters, PureSinusoidsOnABin) {
  const std::vector<Curve> curves = {{1.0, Bin(3), 0.4, 0.0}, {0.7, Bin(1), -1.0, -0.3},
                                     {2.5, Bin(10), 2.0, 4.0}, {0.5, Bin(25), 0.0, 1.0}};
  std::vector<torch::Tensor> rows;
  for (const Curve& c : curves) rows.push_back(Sinusoid(c.a, c.f, c.phi, c.b));
  const torch::Tensor z = torch::stack(rows).view({2, 2, kWindow});  // [B, D, H]
  for (auto dtype : {torch::kFloat64, torch::kFloat32}) {
    const FourierParameters p = ComputeFourierParameters(z.to(dtype), kRate);
    ASSERT_EQ(p.frequency.sizes(), torch::IntArrayRef({2, 2}));
    ASSERT_EQ(p.amplitude.sizes(), torch::IntArrayRef({2, 2}));
    ASSERT_EQ(p.offset.sizes(), torch::IntArrayRef({2, 2}));
    const double tolerance = dtype == torch::kFloat64 ? 1e-6 : 1e-4;
    for (int i = 0; i < 4; ++i) {
      const Curve& c = curves[i];
      const std::string what =
          "curve " + std::to_string(i) + (dtype == torch::kFloat64 ? " (double)" : " (float)");
      ExpectRelative(p.frequency[i / 2][i % 2].item<double>(), c.f, tolerance, what);
      ExpectRelative(p.amplitude[i / 2][i % 2].item<double>(), c.a, tolerance, what);
      EXPECT_NEAR(p.offset[i / 2][i % 2].item<double>(), c.b, tolerance * (1.0 + std::abs(c.b))) << what;
    }
  }
}

// Two bins: F is their power-weighted mean frequency, A the root of the summed squares.
TEST(ComputeFourierParameters, TwoSinusoidsWeightFrequencyByPower) {
  const double a1 = 1.2, a2 = 0.5;
  const torch::Tensor z =
      (Sinusoid(a1, Bin(2), 0.3, 0.0) + Sinusoid(a2, Bin(5), -2.0, 0.25)).view({1, 1, kWindow});
  const FourierParameters p = ComputeFourierParameters(z, kRate);
  const double weighted = (Bin(2) * a1 * a1 + Bin(5) * a2 * a2) / (a1 * a1 + a2 * a2);
  ExpectRelative(p.frequency.item<double>(), weighted, 1e-6, "F");
  ExpectRelative(p.amplitude.item<double>(), std::sqrt(a1 * a1 + a2 * a2), 1e-6, "A");
  EXPECT_NEAR(p.offset.item<double>(), 0.25, 1e-9);
}

TEST(ComputeFourierParameters, ConstantCurveHasNoAmplitude) {
  const torch::Tensor z = torch::full({1, 3, kWindow}, 2.5);
  const FourierParameters p = ComputeFourierParameters(z, kRate);
  // sqrt(eps) = 1e-4 remains: the eps keeps the gradient of sqrt finite.
  EXPECT_TRUE((p.amplitude < 1e-3).all().item<bool>()) << p.amplitude;
  EXPECT_TRUE(torch::allclose(p.offset, torch::full({1, 3}, 2.5), 0.0, 1e-6)) << p.offset;
  EXPECT_TRUE(torch::isfinite(p.frequency).all().item<bool>()) << p.frequency;
}

PaeConfig SmallConfig() {
  PaeConfig c;
  c.latent_channels = 4;
  c.hidden_channels = 8;
  c.kernel_size = 9;
  return c;
}

// Makes the phase layer ignore the latent curves and point at (cos 2 pi phi, sin 2 pi phi).
void FixPhase(PeriodicAutoencoder& pae, double phi) {
  torch::NoGradGuard no_grad;
  auto params = pae->named_parameters();
  params["phase_weight"].zero_();
  torch::Tensor bias = params["phase_bias"];
  bias.select(1, 0).fill_(std::cos(2.0 * M_PI * phi));
  bias.select(1, 1).fill_(std::sin(2.0 * M_PI * phi));
}

TEST(PeriodicAutoencoder, TimeWindowIsCentredOnTheWindow) {
  PeriodicAutoencoder pae(kChannels, kWindow, kRate, SmallConfig());
  const torch::Tensor t = pae->time_window();
  ASSERT_EQ(t.sizes(), torch::IntArrayRef({kWindow}));
  // -0.5 s to 0.5 s in steps of 1/50 s: the newest frame sits at +dt/2.
  for (int i = 0; i < kWindow; ++i) EXPECT_NEAR(t[i].item<double>(), -0.5 + i / kRate, 1e-6) << i;
  EXPECT_EQ(pae->window(), kWindow);
  EXPECT_EQ(pae->latent_channels(), 4);
}

// Eqs. 4 and 8 read back from the outputs, with the phase pinned to 0.2 cycles.
TEST(PeriodicAutoencoder, ForwardFollowsEquations4And8) {
  torch::manual_seed(0);
  PeriodicAutoencoder pae(kChannels, kWindow, kRate, SmallConfig());
  FixPhase(pae, 0.2);
  const int64_t batch = 3, d = 4;
  const torch::Tensor x = torch::randn({batch, kChannels, kWindow});
  const PaeOutput out = pae->Forward(x);
  ASSERT_EQ(out.latent.sizes(), torch::IntArrayRef({batch, d, kWindow}));
  ASSERT_EQ(out.latent_signal.sizes(), torch::IntArrayRef({batch, d, kWindow}));
  ASSERT_EQ(out.reconstruction.sizes(), torch::IntArrayRef({batch, kChannels, kWindow}));
  ASSERT_EQ(out.manifold.sizes(), torch::IntArrayRef({batch, 2 * d}));
  EXPECT_TRUE(torch::allclose(out.phase, torch::full({batch, d}, 0.2), 0.0, 1e-6)) << out.phase;

  const torch::Tensor t = pae->time_window();
  for (int64_t b = 0; b < batch; ++b) {
    for (int64_t c = 0; c < d; ++c) {
      const double f = out.frequency[b][c].item<double>(), a = out.amplitude[b][c].item<double>(),
                   offset = out.offset[b][c].item<double>();
      const double tolerance = 1e-5 * (1.0 + a + std::abs(offset));
      for (int i = 0; i < kWindow; ++i) {
        const double expected = a * std::sin(2.0 * M_PI * (f * t[i].item<double>() + 0.2)) + offset;
        ASSERT_NEAR(out.latent_signal[b][c][i].item<double>(), expected, tolerance)
            << "[" << b << ", " << c << ", " << i << "]";
      }
      // Eq. 8 at the newest frame, T = 0.5 s; cos and sin interleaved per channel.
      const double angle = 2.0 * M_PI * (f * 0.5 + 0.2);
      EXPECT_NEAR(out.manifold[b][2 * c].item<double>(), a * std::cos(angle), 1e-5 * (1.0 + a));
      EXPECT_NEAR(out.manifold[b][2 * c + 1].item<double>(), a * std::sin(angle), 1e-5 * (1.0 + a));
    }
  }
  // The F, A, B of the output are those of its latent curves.
  const FourierParameters p = ComputeFourierParameters(out.latent, kRate);
  EXPECT_TRUE(torch::equal(p.frequency, out.frequency));
  EXPECT_TRUE(torch::equal(p.amplitude, out.amplitude));
  EXPECT_TRUE(torch::equal(p.offset, out.offset));
}

TEST(PeriodicAutoencoder, ManifoldIsForwardsManifold) {
  torch::manual_seed(1);
  PeriodicAutoencoder pae(kChannels, kWindow, kRate, SmallConfig());
  const torch::Tensor x = torch::randn({5, kChannels, kWindow});
  const torch::Tensor manifold = pae->Manifold(x);
  EXPECT_TRUE(torch::equal(manifold, pae->Forward(x).manifold));
  // The learned phase is in cycles, within (-0.5, 0.5].
  const torch::Tensor phase = pae->Forward(x).phase;
  EXPECT_TRUE((phase > -0.5).all().item<bool>() && (phase <= 0.5).all().item<bool>()) << phase;
}

// A stream of three episodes' segments as MotionStreams lays them out (H - 1 copies of a first
// frame, then motion), and windows ending anywhere in a segment, including at its first frames
// and at the last: ManifoldAlong reads the same manifold as Manifold of the cut-out windows, with
// either padding, a kernel wider than the window's half, and more windows than one chunk.
TEST(PeriodicAutoencoder, ManifoldAlongAStreamIsManifoldOfItsWindows) {
  for (bool replicate : {true, false}) {
    for (int kernel : {1, 9, 31, 61}) {
      torch::manual_seed(7);
      PaeConfig c = SmallConfig();
      c.replicate_padding = replicate;
      c.kernel_size = kernel;
      PeriodicAutoencoder pae(kChannels, kWindow, kRate, c);
      std::vector<torch::Tensor> segments;
      std::vector<int64_t> ends;
      int64_t length = 0;
      for (int episode = 0; episode < 3; ++episode) {
        const int64_t steps = 200 + 150 * episode;
        const torch::Tensor first = torch::randn({kChannels, 1});
        segments.push_back(first.expand({kChannels, kWindow - 1}));
        segments.push_back(torch::randn({kChannels, steps}));
        for (int64_t k = 0; k < steps; ++k) ends.push_back(length + kWindow - 1 + k);
        length += kWindow - 1 + steps;
      }
      const torch::Tensor frames = torch::cat(segments, 1);
      const torch::Tensor end_columns = torch::tensor(ends, torch::kLong);
      torch::NoGradGuard no_grad;
      const torch::Tensor along = pae->ManifoldAlong(frames, end_columns);
      const torch::Tensor cut = pae->Manifold(WindowsAlong(frames, end_columns, kWindow));
      SCOPED_TRACE(testing::Message() << (replicate ? "replicate" : "zero") << " padding, kernel " << kernel);
      ASSERT_EQ(along.sizes(), cut.sizes());
      EXPECT_LT((along - cut).abs().max().item<double>(), 1e-4 * (1.0 + cut.abs().max().item<double>()));
    }
  }
}

// Eq. 3: ||o - o^||^2 / H per window, averaged over the batch.
TEST(PeriodicAutoencoder, LossIsSquaredErrorOverHAveragedOverTheBatch) {
  PeriodicAutoencoder pae(kChannels, kWindow, kRate, SmallConfig());
  // Small integers, so that x + 1 - x is exactly 1 in float.
  const torch::Tensor x = torch::randint(-8, 8, {2, kChannels, kWindow}).to(torch::kFloat32);
  PaeOutput out;
  out.reconstruction = x + 1.0;
  EXPECT_FLOAT_EQ(pae->Loss(x, out).item<float>(), 33.0f);  // 33 * 51 ones / 51
  // Window 0 off by 1, window 1 off by 2: (33 + 4 * 33) / 2.
  out.reconstruction = x + torch::tensor({1.0f, 2.0f}).view({2, 1, 1});
  EXPECT_FLOAT_EQ(pae->Loss(x, out).item<float>(), 82.5f);
  out.reconstruction = x;
  EXPECT_EQ(pae->Loss(x, out).item<float>(), 0.0f);
}

void ExpectUsefulGradient(const torch::Tensor& grad, const std::string& name) {
  ASSERT_TRUE(grad.defined()) << name << " has no gradient";
  EXPECT_TRUE(torch::isfinite(grad).all().item<bool>()) << name;
  EXPECT_GT(grad.abs().sum().item<double>(), 0.0) << name;
}

TEST(PeriodicAutoencoder, EveryParameterGetsAGradient) {
  torch::manual_seed(2);
  PeriodicAutoencoder pae(kChannels, kWindow, kRate, SmallConfig());
  const torch::Tensor x = torch::randn({4, kChannels, kWindow});
  pae->Loss(x, pae->Forward(x)).backward();
  int count = 0;
  for (const auto& item : pae->named_parameters()) {
    ExpectUsefulGradient(item.value().grad(), item.key());
    ++count;
  }
  // encoder1, encoder2, decoder1, decoder2 (weight and bias), 4 norm vectors, phase weight and bias
  EXPECT_EQ(count, 14);
}

// With the phase layer ignoring z, the encoder's only way to the loss is the differentiable
// Fourier layer (rfft -> F, A, B).
TEST(PeriodicAutoencoder, EncoderLearnsThroughTheFourierLayer) {
  torch::manual_seed(3);
  PeriodicAutoencoder pae(kChannels, kWindow, kRate, SmallConfig());
  FixPhase(pae, 0.1);
  const torch::Tensor x = torch::randn({4, kChannels, kWindow});
  const PaeOutput out = pae->Forward(x);
  auto params = pae->named_parameters();
  // Through F alone: the gradient of F reaches the first encoder layer.
  out.frequency.sum().backward();
  ExpectUsefulGradient(params["encoder1.weight"].grad(), "encoder1.weight via F");
  pae->zero_grad();
  pae->Loss(x, pae->Forward(x)).backward();
  ExpectUsefulGradient(params["encoder1.weight"].grad(), "encoder1.weight");
  ExpectUsefulGradient(params["encoder2.weight"].grad(), "encoder2.weight");
  ExpectUsefulGradient(params["phase_weight"].grad(), "phase_weight");  // through atan2
}

// A still window says nothing about the posture it holds: with the end frames repeated, two
// constant windows at different levels meet at one manifold point. With zero padding, the
// window's ends carry its level through the encoder, and the points are far apart.
TEST(PeriodicAutoencoder, StillPosturesShareAManifoldPointOnlyWithReplicatePadding) {
  const torch::Tensor crouch = torch::full({1, kChannels, kWindow}, -0.8);
  const torch::Tensor stand = torch::linspace(-1.0, 1.0, kChannels).view({1, kChannels, 1}).expand({1, kChannels, kWindow});
  const torch::Tensor stills = torch::cat({crouch, stand}, 0);
  for (bool replicate : {true, false}) {
    torch::manual_seed(5);
    PaeConfig c = SmallConfig();
    c.replicate_padding = replicate;
    PeriodicAutoencoder pae(kChannels, kWindow, kRate, c);
    torch::NoGradGuard no_grad;
    const torch::Tensor p = pae->Manifold(stills);
    const double gap = (p[0] - p[1]).norm().item<double>();
    const double size = p.norm().item<double>();
    if (replicate) {
      EXPECT_LT(gap, 1e-4 * size) << p;
    } else {
      EXPECT_GT(gap, 0.1 * size) << p;
    }
  }
}

// A posture's tremor against a gait's swing, the same curve at 1/100 of the amplitude. With
// DeepPhase's epsilon the encoder's time normalisation brings both to one amplitude, so the
// discriminator would tell postures apart by tremor; with an epsilon of 1 the tremor's manifold
// point stays near the origin.
TEST(PeriodicAutoencoder, ATremorStaysSmallOnlyWithALargeEncoderEpsilon) {
  const torch::Tensor t = torch::arange(kWindow, torch::kFloat32) / kRate;
  const torch::Tensor curves = torch::sin(2.0 * M_PI * 2.0 * t + torch::linspace(0.0, 3.0, kChannels).view({kChannels, 1}));
  const torch::Tensor windows = torch::stack({curves, 0.01 * curves}, 0);
  for (double epsilon : {1e-5, 1.0}) {
    torch::manual_seed(6);
    PaeConfig c = SmallConfig();
    c.encoder_norm_epsilon = epsilon;
    PeriodicAutoencoder pae(kChannels, kWindow, kRate, c);
    torch::NoGradGuard no_grad;
    const torch::Tensor p = pae->Manifold(windows);
    const double ratio = p[1].norm().item<double>() / p[0].norm().item<double>();
    if (epsilon < 1e-3) {
      EXPECT_GT(ratio, 0.5) << "epsilon " << epsilon;
    } else {
      EXPECT_LT(ratio, 0.2) << "epsilon " << epsilon;
    }
  }
}

TEST(PeriodicAutoencoder, EvenKernelIsRejected) {
  PaeConfig c = SmallConfig();
  c.kernel_size = 8;
  EXPECT_THAT(InputErrorMessage([&] { PeriodicAutoencoder pae(kChannels, kWindow, kRate, c); }),
              HasSubstr("kernel_size"));
}

}  // namespace
}  // namespace flsd
