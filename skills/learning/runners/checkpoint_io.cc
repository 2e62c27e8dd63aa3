#include "skills/learning/runners/checkpoint_io.h"

#include <sstream>

#include "core/check.h"

namespace flsd {

torch::serialize::InputArchive OpenCheckpoint(const std::string& path) {
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(path);
  } catch (const c10::Error& e) {
    throw InputError(path + ": not a readable checkpoint: " + e.what_without_backtrace());
  }
  return archive;
}

void WriteModule(torch::serialize::OutputArchive& archive, const char* key, const torch::nn::Module& m) {
  torch::serialize::OutputArchive sub;
  m.save(sub);
  archive.write(key, sub);
}

void WriteOptimizer(torch::serialize::OutputArchive& archive, const char* key, const torch::optim::Optimizer& o) {
  torch::serialize::OutputArchive sub;
  o.save(sub);
  archive.write(key, sub);
}

void ReadModule(torch::serialize::InputArchive& archive, const char* key, torch::nn::Module& m) {
  struct Kept {
    std::string name;
    torch::Tensor live, copy;
  };
  std::vector<Kept> kept;
  for (const auto& p : m.named_parameters()) kept.push_back({p.key(), p.value(), p.value().detach().clone()});
  for (const auto& b : m.named_buffers()) kept.push_back({b.key(), b.value(), b.value().detach().clone()});
  auto restore = [&] {
    torch::NoGradGuard no_grad;
    for (const Kept& k : kept) k.live.set_(k.copy);
  };
  try {
    torch::serialize::InputArchive sub;
    archive.read(key, sub);
    m.load(sub);
  } catch (...) {
    restore();
    throw;
  }
  for (const Kept& k : kept) {
    if (k.live.sizes() == k.copy.sizes()) continue;
    const std::string message = std::string("checkpoint tensor ") + key + "." + k.name + " has shape " +
                                c10::str(k.live.sizes()) + " but this training config needs " + c10::str(k.copy.sizes());
    restore();
    throw InputError(message);
  }
}

void ReadOptimizer(torch::serialize::InputArchive& archive, const char* key, torch::optim::Optimizer& o) {
  torch::serialize::InputArchive sub;
  archive.read(key, sub);
  o.load(sub);
}

int64_t ReadInt(torch::serialize::InputArchive& archive, const char* key) {
  c10::IValue value;
  archive.read(key, value);
  return value.toInt();
}

double ReadDouble(torch::serialize::InputArchive& archive, const char* key) {
  c10::IValue value;
  archive.read(key, value);
  return value.toDouble();
}

std::string ReadString(torch::serialize::InputArchive& archive, const char* key) {
  c10::IValue value;
  archive.read(key, value);
  return value.toStringRef();
}

void WriteTorchRng(torch::serialize::OutputArchive& archive) {
  archive.write("torch_rng", at::detail::getDefaultCPUGenerator().get_state());
}

void ReadTorchRng(torch::serialize::InputArchive& archive) {
  torch::Tensor state;
  archive.read("torch_rng", state);
  at::Generator generator = at::detail::getDefaultCPUGenerator();  // a handle to the global one
  generator.set_state(state);
}

std::string RngState(const std::vector<Rng>& rngs) {
  std::ostringstream out;
  for (const Rng& r : rngs) out << r << '\n';
  return out.str();
}

void RestoreRngState(const std::string& state, std::vector<Rng>& rngs, const std::string& what) {
  std::istringstream in(state);
  for (Rng& r : rngs) in >> r;
  in >> std::ws;
  if (!in || !in.eof()) throw InputError("checkpoint: " + what + " random-number states do not match num_envs");
}

void MismatchedCheckpoint(const std::string& path, const c10::Error& e) {
  throw InputError(path + ": checkpoint does not fit this training config (" +
                   std::string(e.what_without_backtrace()) + ")");
}

}  // namespace flsd
