#include "skills/learning/networks/pae.h"

#include <cmath>

#include "core/check.h"
#include "skills/learning/networks/motion_streams.h"

namespace flsd {
namespace {

// Guards sqrt and division against an all-constant latent curve (zero spectral power).
constexpr double kEps = 1e-8;
// DeepPhase's layer-norm epsilon, kept in the decoder.
constexpr double kDecoderNormEpsilon = 1e-5;
// ManifoldAlong takes windows through the encoder in chunks of this many (measured: 512 runs 16 %
// faster than 4096, whose activations fall out of cache).
constexpr int64_t kWindowChunk = 512;

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
      kernel_size_(config.kernel_size),
      replicate_padding_(config.replicate_padding),
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
  return EncodeFromFirstLayer(encoder1_(windows));
}

torch::Tensor PeriodicAutoencoderImpl::EncodeFromFirstLayer(const torch::Tensor& first) {
  return encoder2_(torch::elu(TimeNorm(first, encoder_norm_weight_, encoder_norm_bias_, encoder_norm_epsilon_)));
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

torch::Tensor PeriodicAutoencoderImpl::ManifoldOfLatent(const torch::Tensor& z) {
  return ManifoldOf(ComputeFourierParameters(z, sample_rate_hz_), Phase(z));
}

torch::Tensor PeriodicAutoencoderImpl::Manifold(const torch::Tensor& windows) { return ManifoldOfLatent(Encode(windows)); }

torch::Tensor PeriodicAutoencoderImpl::FirstLayerAtEdge(const torch::Tensor& edge_frames, bool start) {
  namespace F = torch::nn::functional;
  const int64_t pad = (kernel_size_ - 1) / 2;
  F::PadFuncOptions options(start ? std::vector<int64_t>{pad, 0} : std::vector<int64_t>{0, pad});
  if (replicate_padding_) options.mode(torch::kReplicate);
  return torch::conv1d(F::pad(edge_frames, options), encoder1_->weight, encoder1_->bias);
}

torch::Tensor PeriodicAutoencoderImpl::ManifoldAlong(const torch::Tensor& frames, const torch::Tensor& ends) {
  FLSD_DEMAND(frames.dim() == 2 && ends.dim() == 1);
  const int64_t pad = (kernel_size_ - 1) / 2, interior = window_ - 2 * pad;
  std::vector<torch::Tensor> parts;
  if (pad == 0 || interior < 0) {  // no padding to treat apart, or a kernel wider than the window
    for (int64_t begin = 0; begin < ends.size(0); begin += kWindowChunk) {
      const torch::Tensor chunk = ends.slice(0, begin, begin + kWindowChunk);
      parts.push_back(Manifold(WindowsAlong(frames, chunk, window_)));
    }
    return torch::cat(parts, 0);
  }
  // Column p of the unpadded convolution is centred on stream frame p + pad.
  const torch::Tensor stream = torch::conv1d(frames.unsqueeze(0), encoder1_->weight, encoder1_->bias).squeeze(0);
  const int64_t hidden = stream.size(0);
  for (int64_t begin = 0; begin < ends.size(0); begin += kWindowChunk) {
    const torch::Tensor chunk = ends.slice(0, begin, begin + kWindowChunk);
    const int64_t count = chunk.size(0);
    const torch::Tensor first_frame = chunk - (window_ - 1);
    // Window positions pad .. H - 1 - pad, centred on frames start + pad onwards.
    const torch::Tensor columns = first_frame.unsqueeze(1) + torch::arange(interior, torch::kLong);
    const torch::Tensor middle =
        stream.index_select(1, columns.reshape({-1})).view({hidden, count, interior}).permute({1, 0, 2});
    const torch::Tensor start = FirstLayerAtEdge(WindowsAlong(frames, first_frame + (2 * pad - 1), 2 * pad), true);
    const torch::Tensor end = FirstLayerAtEdge(WindowsAlong(frames, chunk, 2 * pad), false);
    parts.push_back(ManifoldOfLatent(EncodeFromFirstLayer(torch::cat({start, middle, end}, 2))));
  }
  return torch::cat(parts, 0);
}

double PeriodicAutoencoderImpl::ForwardMacsPerWindow() const {
  const double convolutions = static_cast<double>(encoder1_->weight.numel() + encoder2_->weight.numel() +
                                                  decoder1_->weight.numel() + decoder2_->weight.numel());
  return (convolutions + static_cast<double>(phase_weight_.numel())) * window_;
}

double PeriodicAutoencoderImpl::ManifoldAlongMacs(int64_t columns, int64_t windows) const {
  const double first = static_cast<double>(encoder1_->weight.numel());
  const double rest = static_cast<double>(encoder2_->weight.numel() + phase_weight_.numel()) * window_;
  const int64_t pad = (kernel_size_ - 1) / 2;
  if (pad == 0 || window_ < 2 * pad) return windows * (first * window_ + rest);  // ManifoldAlong's fallback
  // The stream's unpadded convolution, then 2 pad edge columns and the rest per window.
  return first * (columns - 2 * pad) + windows * (first * 2 * pad + rest);
}

torch::Tensor PeriodicAutoencoderImpl::Loss(const torch::Tensor& windows, const PaeOutput& out) const {
  return (windows - out.reconstruction).pow(2).sum({1, 2}).mean() / static_cast<double>(window_);
}

}  // namespace flsd
