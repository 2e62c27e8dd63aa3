#pragma once
// Reading and writing the parts of a training checkpoint (libtorch archives), shared by the skill
// trainer and the task trainer. Every read checks what it reads, so that a checkpoint from another
// config is an error that names the file and the tensor, not a crash later.

#include <torch/torch.h>

#include <string>
#include <vector>

#include "core/rng.h"

namespace flsd {

// Opens `path`; throws InputError naming it if it is not a readable archive.
torch::serialize::InputArchive OpenCheckpoint(const std::string& path);

void WriteModule(torch::serialize::OutputArchive& archive, const char* key, const torch::nn::Module& m);
void WriteOptimizer(torch::serialize::OutputArchive& archive, const char* key, const torch::optim::Optimizer& o);

// Module::load replaces tensors whatever their shape, so the shapes are checked here: a module
// whose shapes differ from the archive's is left as it was, and InputError names the tensor.
void ReadModule(torch::serialize::InputArchive& archive, const char* key, torch::nn::Module& m);
void ReadOptimizer(torch::serialize::InputArchive& archive, const char* key, torch::optim::Optimizer& o);
int64_t ReadInt(torch::serialize::InputArchive& archive, const char* key);
double ReadDouble(torch::serialize::InputArchive& archive, const char* key);
std::string ReadString(torch::serialize::InputArchive& archive, const char* key);

// libtorch's global generator state, saved and restored so that a resumed run draws on.
void WriteTorchRng(torch::serialize::OutputArchive& archive);
void ReadTorchRng(torch::serialize::InputArchive& archive);

// Per-env random streams as text; Restore throws InputError if the count differs.
std::string RngState(const std::vector<Rng>& rngs);
void RestoreRngState(const std::string& state, std::vector<Rng>& rngs, const std::string& what);

// Rethrows a libtorch error met while reading `path` as an InputError naming it.
[[noreturn]] void MismatchedCheckpoint(const std::string& path, const c10::Error& e);

}  // namespace flsd
