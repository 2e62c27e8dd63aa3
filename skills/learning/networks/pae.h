#pragma once
// The Periodic Autoencoder of the paper's Sec. III-A (Eqs. 2-8), after DeepPhase (Starke et al.
// 2022) and FLD (Li et al. 2024): a temporal-convolution encoder maps a window of motion
// observations [C x H] to D latent curves; a differentiable Fourier layer reads each curve's
// frequency F, amplitude A and offset B; a per-channel linear layer reads its phase Phi; each
// curve is replaced by the sinusoid A sin(2 pi (F T + Phi)) + B, which the decoder maps back.
// The phase manifold P (Eq. 8), 2D values, is what the discriminator sees.

#include <torch/torch.h>

#include "core/config.h"

namespace flsd {

struct PaeConfig {
  int latent_channels = 8;    // D; FLD uses 8
  int hidden_channels = 16;   // encoder/decoder width; DeepPhase uses C/3, FLD 64
  int kernel_size = 15;       // temporal kernel (odd); DeepPhase and FLD use H
  double learning_rate = 1e-4;  // AdamW, as DeepPhase
  double weight_decay = 1e-4;
  int epochs = 1;             // passes over the sampled windows per iteration
  int minibatch_size = 512;
  double sample_fraction = 0.25;  // share of an iteration's windows the PAE trains on
  // The convolutions extend the window by repeating its end frames, not by zeros. With zeros, the
  // ends of a still window carry its level through the encoder (the time normalisation removes
  // only the mean and the scale), so a still posture has a manifold point of its own and the
  // discriminator tells postures apart: the single-step state that FLSD means to replace.
  bool replicate_padding = true;
  // The encoder's time normalisation adds this to each curve's variance before dividing by its
  // root. DeepPhase's 1e-5 scales a still posture's millimetre tremor up to a gait's amplitude, so
  // the discriminator tells postures apart by their tremor; at 1 (the order of a gait's variance
  // in o^m's units) a curve much smaller than a gait stays small.
  double encoder_norm_epsilon = 1e-5;
  template <class V>
  void Visit(V& v) {
    v("latent_channels", latent_channels, Bounds<int>{1, 64});
    v("hidden_channels", hidden_channels, Bounds<int>{1, 1024});
    v("kernel_size", kernel_size, Bounds<int>{1, 1001});
    v("learning_rate", learning_rate, Bounds<double>{0.0, 1.0});
    v("weight_decay", weight_decay, Bounds<double>{0.0, 1.0});
    v("epochs", epochs, Bounds<int>{0, 1000});
    v("minibatch_size", minibatch_size, Bounds<int>{1, 1 << 20});
    v("sample_fraction", sample_fraction, Bounds<double>{0.0, 1.0});
    v("replicate_padding", replicate_padding);
    v("encoder_norm_epsilon", encoder_norm_epsilon, Bounds<double>{1e-12, 1e3});
  }
};

// Every intermediate of one PAE pass over a batch of windows [B, C, H].
struct PaeOutput {
  torch::Tensor latent;          // z, [B, D, H]
  torch::Tensor frequency;       // F, [B, D], Hz
  torch::Tensor amplitude;       // A, [B, D]
  torch::Tensor offset;          // B, [B, D]
  torch::Tensor phase;           // Phi, [B, D], cycles in (-0.5, 0.5]
  torch::Tensor latent_signal;   // z^ = A sin(2 pi (F T + Phi)) + B, [B, D, H]
  torch::Tensor reconstruction;  // o^H^, [B, C, H]
  torch::Tensor manifold;        // P, [B, 2D]: (A cos a, A sin a) per channel, Eq. 8
};

// F, A and B of each latent curve (Eqs. 5-6); z is [B, D, H] sampled at sample_rate_hz.
struct FourierParameters {
  torch::Tensor frequency, amplitude, offset;
};
FourierParameters ComputeFourierParameters(const torch::Tensor& z, double sample_rate_hz);

class PeriodicAutoencoderImpl : public torch::nn::Module {
 public:
  // input_channels C (33 for o^m), window H (51), sample rate (50 Hz).
  PeriodicAutoencoderImpl(int input_channels, int window, double sample_rate_hz, const PaeConfig& config);

  PaeOutput Forward(const torch::Tensor& windows);
  // Encoder, Fourier layer and phase only: the manifold P [B, 2D], for rewards.
  torch::Tensor Manifold(const torch::Tensor& windows);
  // Manifold(WindowsAlong(frames, ends, H)) for the windows of a motion stream [C, L] ending at
  // columns `ends` [B], without cutting the windows out: the first convolution's outputs away
  // from a window's ends depend only on the stream, so it runs once over the stream, and only
  // the padded ends are convolved per window (equal up to float rounding).
  torch::Tensor ManifoldAlong(const torch::Tensor& frames, const torch::Tensor& ends);
  // Eq. 3: ||o^H - o^H^||^2 / H, averaged over the batch.
  torch::Tensor Loss(const torch::Tensor& windows, const PaeOutput& out) const;

  // Multiply-accumulates of the convolutions and the phase layer (what dominates the arithmetic):
  // of Forward per window, and of ManifoldAlong over a stream of `columns` frames and `windows`
  // windows.
  double ForwardMacsPerWindow() const;
  double ManifoldAlongMacs(int64_t columns, int64_t windows) const;

  int window() const { return window_; }
  int latent_channels() const { return latent_channels_; }
  // The centred time window T (Sec. III-A): H times from -dt/2 to dt/2, dt = (H - 1) / rate.
  const torch::Tensor& time_window() const { return time_window_; }

 private:
  torch::Tensor Encode(const torch::Tensor& windows);
  // The encoder after its first convolution, from that convolution's output [B, hidden, H].
  torch::Tensor EncodeFromFirstLayer(const torch::Tensor& first);
  // The first convolution's outputs at the `pad` positions of each window's start (or end) next
  // to the padding, from the window's first (or last) 2 pad frames [B, C, 2 pad].
  torch::Tensor FirstLayerAtEdge(const torch::Tensor& edge_frames, bool start);
  torch::Tensor ManifoldOfLatent(const torch::Tensor& z);
  torch::Tensor Phase(const torch::Tensor& z);  // Eq. 7
  torch::Tensor ManifoldOf(const FourierParameters& f, const torch::Tensor& phase) const;  // Eq. 8

  int window_;
  int latent_channels_;
  int kernel_size_;
  bool replicate_padding_;
  double sample_rate_hz_;
  double encoder_norm_epsilon_;
  torch::nn::Conv1d encoder1_{nullptr}, encoder2_{nullptr}, decoder1_{nullptr}, decoder2_{nullptr};
  torch::Tensor encoder_norm_weight_, encoder_norm_bias_, decoder_norm_weight_, decoder_norm_bias_;
  torch::Tensor phase_weight_, phase_bias_;  // one Linear(H -> 2) per channel: [D, 2, H], [D, 2]
  torch::Tensor time_window_;
};
TORCH_MODULE(PeriodicAutoencoder);

}  // namespace flsd
