#include "skills/learning/networks/pae.h"

#include <cmath>

#include "core/check.h"

namespace flsd {
namespace {

// Guards sqrt and division against an all-constant latent curve (zero spectral power).
constexpr double kEps = 1e-8;
// DeepPhase's layer-norm epsilon, kept in the decoder.
constexpr double kDecoderNormEpsilon = 1e-5;

// A convolution whose output is as long as its input: padded by zeros or by repeated end frames.
torch::nn::Conv1d SameConv(int in, int out, int kernel, bool replicate) {
  torch::nn::Conv1dOptions options(in, out, kernel);
  options.padding((kernel - 1) / 2);
  if (replicate) options.padding_mode(torch::kReplicate);
  return torch::nn::Conv1d(options);
}

// DeepPhase's LN_v2: each (sample, channel) curve normalised over time, with a learned gain and
// bias per time step.
torch::Tensor TimeNorm(const torch::Tensor& x, const torch::Tensor& weight, const torch::Tensor& bias,
                       double epsilon) {
  return torch::layer_norm(x, {x.size(2)}, weight, bias, epsilon);
}

}  // namespace

FourierParameters ComputeFourierParameters(const torch::Tensor& z, double sample_rate_hz) {
  const int64_t h = z.size(2);
  const int64_t m = h / 2;
  const torch::Tensor c = torch::fft_rfft(z, c10::nullopt, 2);  // [B, D, M + 1]
  // Eq. 5: p = 2/H |c|^2, for the non-DC bins j = 1..M.
  const torch::Tensor power = (2.0 / h) * c.slice(2, 1, m + 1).abs().pow(2);
  const torch::Tensor freqs =
      torch::arange(1, m + 1, z.options()) * (sample_rate_hz / static_cast<double>(h));
  const torch::Tensor total = power.sum(2);
  FourierParameters f;
  f.frequency = (power * freqs).sum(2) / (total + kEps);            // Eq. 6, F
  f.amplitude = torch::sqrt((2.0 / h) * total + kEps);              // Eq. 6, A
  f.offset = torch::real(c.select(2, 0)) / static_cast<double>(h);  // Eq. 6, B
  return f;
}

PeriodicAutoencoderImpl::PeriodicAutoencoderImpl(int input_channels, int window, double sample_rate_hz,
                                                 const PaeConfig& config)
    : window_(window),
      latent_channels_(config.latent_channels),
      sample_rate_hz_(sample_rate_hz),
      encoder_norm_epsilon_(config.encoder_norm_epsilon) {
  if (config.kernel_size % 2 == 0) {
    throw InputError("pae.kernel_size must be odd, got " + std::to_string(config.kernel_size));
  }
  const int hidden = config.hidden_channels, d = config.latent_channels, k = config.kernel_size;
  const bool r = config.replicate_padding;
  encoder1_ = register_module("encoder1", SameConv(input_channels, hidden, k, r));
  encoder2_ = register_module("encoder2", SameConv(hidden, d, k, r));
  decoder1_ = register_module("decoder1", SameConv(d, hidden, k, r));
  decoder2_ = register_module("decoder2", SameConv(hidden, input_channels, k, r));
  encoder_norm_weight_ = register_parameter("encoder_norm_weight", torch::ones({window}));
  encoder_norm_bias_ = register_parameter("encoder_norm_bias", torch::zeros({window}));
  decoder_norm_weight_ = register_parameter("decoder_norm_weight", torch::ones({window}));
  decoder_norm_bias_ = register_parameter("decoder_norm_bias", torch::zeros({window}));
  // Initialised as torch::nn::Linear(H, 2) would be, one per channel.
  const double bound = 1.0 / std::sqrt(static_cast<double>(window));
  phase_weight_ = register_parameter("phase_weight", torch::empty({d, 2, window}).uniform_(-bound, bound));
  phase_bias_ = register_parameter("phase_bias", torch::empty({d, 2}).uniform_(-bound, bound));
  const double span = (window - 1) / sample_rate_hz;
  time_window_ = register_buffer("time_window", torch::linspace(-span / 2, span / 2, window));
}

torch::Tensor PeriodicAutoencoderImpl::Encode(const torch::Tensor& windows) {
  FLSD_DEMAND(windows.dim() == 3 && windows.size(2) == window_);
  return encoder2_(
      torch::elu(TimeNorm(encoder1_(windows), encoder_norm_weight_, encoder_norm_bias_, encoder_norm_epsilon_)));
}

torch::Tensor PeriodicAutoencoderImpl::Phase(const torch::Tensor& z) {
  // (s_x, s_y) of channel i from its own curve: [B, D, H] x [D, 2, H] -> [B, D, 2].
  const torch::Tensor s = torch::einsum("bdh,dkh->bdk", {z, phase_weight_}) + phase_bias_;
  return torch::atan2(s.select(2, 1), s.select(2, 0)) / (2.0 * M_PI);
}

torch::Tensor PeriodicAutoencoderImpl::ManifoldOf(const FourierParameters& f, const torch::Tensor& phase) const {
  // The current frame sits at the end of the centred window, T = (H - 1) / rate / 2.
  const double half_span = (window_ - 1) / sample_rate_hz_ / 2.0;
  const torch::Tensor angle = 2.0 * M_PI * (f.frequency * half_span + phase);
  const torch::Tensor p = torch::stack({f.amplitude * torch::cos(angle), f.amplitude * torch::sin(angle)}, 2);
  return p.reshape({p.size(0), 2 * latent_channels_});
}

PaeOutput PeriodicAutoencoderImpl::Forward(const torch::Tensor& windows) {
  PaeOutput out;
  out.latent = Encode(windows);
  const FourierParameters f = ComputeFourierParameters(out.latent, sample_rate_hz_);
  out.frequency = f.frequency;
  out.amplitude = f.amplitude;
  out.offset = f.offset;
  out.phase = Phase(out.latent);
  // Eq. 4 over the centred window.
  const torch::Tensor t = time_window_.view({1, 1, window_});
  out.latent_signal =
      f.amplitude.unsqueeze(2) *
          torch::sin(2.0 * M_PI * (f.frequency.unsqueeze(2) * t + out.phase.unsqueeze(2))) +
      f.offset.unsqueeze(2);
  out.reconstruction = decoder2_(
      torch::elu(TimeNorm(decoder1_(out.latent_signal), decoder_norm_weight_, decoder_norm_bias_, kDecoderNormEpsilon)));
  out.manifold = ManifoldOf(f, out.phase);
  return out;
}

torch::Tensor PeriodicAutoencoderImpl::Manifold(const torch::Tensor& windows) {
  const torch::Tensor z = Encode(windows);
  return ManifoldOf(ComputeFourierParameters(z, sample_rate_hz_), Phase(z));
}

torch::Tensor PeriodicAutoencoderImpl::Loss(const torch::Tensor& windows, const PaeOutput& out) const {
  return (windows - out.reconstruction).pow(2).sum({1, 2}).mean() / static_cast<double>(window_);
}

}  // namespace flsd
