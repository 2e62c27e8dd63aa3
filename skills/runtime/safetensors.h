#pragma once
// The safetensors file format: an 8-byte little-endian header length, a JSON header, then the raw
// little-endian tensor bytes. Any safetensors reader opens our skill libraries. Only float32
// tensors are used. Plain C++: no torch, no Eigen.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace flsd {

struct FloatTensor {
  std::vector<int64_t> shape;
  std::vector<float> values;  // row-major, size = product of shape
};

struct SafeTensors {
  std::map<std::string, std::string> metadata;  // the header's "__metadata__" (strings only)
  std::map<std::string, FloatTensor> tensors;
};

// Writes atomically (temp file, then rename). Throws InputError naming the path on failure.
void WriteSafeTensors(const std::string& path, const SafeTensors& contents);

// Reads and checks the whole file: header length within the file, valid JSON, every tensor F32
// with a shape that matches its byte range, ranges inside the data and not overlapping. Throws
// InputError naming the file and what is wrong; never reads out of bounds.
SafeTensors ReadSafeTensors(const std::string& path);

}  // namespace flsd
