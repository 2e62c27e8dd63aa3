#include "skills/runtime/safetensors.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/check.h"

namespace flsd {
namespace {

static_assert(sizeof(float) == 4, "float32 tensors");

// The header length is limited as the reference implementation limits it (100 MB).
constexpr uint64_t kMaxHeader = 100'000'000;

[[noreturn]] void Fail(const std::string& path, const std::string& what) {
  throw InputError(path + ": not a valid safetensors file: " + what);
}

int64_t Elements(const std::vector<int64_t>& shape) {
  int64_t n = 1;
  for (int64_t d : shape) n *= d;
  return n;
}

}  // namespace

void WriteSafeTensors(const std::string& path, const SafeTensors& contents) {
  nlohmann::json header = nlohmann::json::object();
  if (!contents.metadata.empty()) header["__metadata__"] = contents.metadata;
  uint64_t offset = 0;
  for (const auto& [name, tensor] : contents.tensors) {
    FLSD_DEMAND(static_cast<int64_t>(tensor.values.size()) == Elements(tensor.shape));
    const uint64_t bytes = tensor.values.size() * sizeof(float);
    header[name] = {{"dtype", "F32"}, {"shape", tensor.shape}, {"data_offsets", {offset, offset + bytes}}};
    offset += bytes;
  }
  std::string text = header.dump();
  text.append((8 - text.size() % 8) % 8, ' ');  // the data starts 8-byte aligned
  std::string file(8, '\0');
  const uint64_t length = text.size();
  for (int b = 0; b < 8; ++b) file[b] = static_cast<char>((length >> (8 * b)) & 0xff);
  file += text;
  for (const auto& [name, tensor] : contents.tensors) {
    for (float v : tensor.values) {
      uint32_t bits;
      std::memcpy(&bits, &v, 4);
      for (int b = 0; b < 4; ++b) file.push_back(static_cast<char>((bits >> (8 * b)) & 0xff));
    }
  }
  WriteFileAtomically(path, file);
}

SafeTensors ReadSafeTensors(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  const std::string file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (file.size() < 8) Fail(path, "shorter than the 8-byte header length (" + std::to_string(file.size()) + " bytes)");
  uint64_t length = 0;
  for (int b = 0; b < 8; ++b) length |= static_cast<uint64_t>(static_cast<unsigned char>(file[b])) << (8 * b);
  if (length > kMaxHeader || length > file.size() - 8) {
    Fail(path, "header length " + std::to_string(length) + " runs past the end of the " +
                   std::to_string(file.size()) + "-byte file (truncated?)");
  }
  nlohmann::json header;
  try {
    header = nlohmann::json::parse(file.begin() + 8, file.begin() + 8 + static_cast<std::ptrdiff_t>(length));
  } catch (const nlohmann::json::exception& e) {
    Fail(path, std::string("header is not JSON: ") + e.what());
  }
  if (!header.is_object()) Fail(path, "header is not a JSON object");

  SafeTensors out;
  const uint64_t data_begin = 8 + length;
  const uint64_t data_size = file.size() - data_begin;
  std::vector<std::pair<uint64_t, uint64_t>> ranges;
  for (const auto& [name, entry] : header.items()) {
    if (name == "__metadata__") {
      if (!entry.is_object()) Fail(path, "__metadata__ is not an object");
      for (const auto& [key, value] : entry.items()) {
        if (!value.is_string()) Fail(path, "__metadata__." + key + " is not a string");
        out.metadata[key] = value.get<std::string>();
      }
      continue;
    }
    const std::string where = "tensor '" + name + "'";
    if (!entry.is_object() || !entry.contains("dtype") || !entry.contains("shape") || !entry.contains("data_offsets")) {
      Fail(path, where + " lacks dtype, shape or data_offsets");
    }
    if (entry["dtype"] != "F32") Fail(path, where + " has dtype " + entry["dtype"].dump() + "; expected \"F32\"");
    FloatTensor tensor;
    const nlohmann::json& offsets = entry["data_offsets"];
    uint64_t begin = 0, end = 0;
    try {
      tensor.shape = entry["shape"].get<std::vector<int64_t>>();
      if (!offsets.is_array() || offsets.size() != 2 || !offsets[0].is_number_unsigned() ||
          !offsets[1].is_number_unsigned()) {
        throw std::invalid_argument("offsets");
      }
      begin = offsets[0].get<uint64_t>();
      end = offsets[1].get<uint64_t>();
    } catch (const std::exception&) {
      Fail(path, where + " has a malformed shape or data_offsets");
    }
    int64_t elements = 1;
    for (int64_t d : tensor.shape) {
      if (d < 0 || (d > 0 && elements > (int64_t{1} << 40) / d)) Fail(path, where + " has an invalid shape");
      elements *= d;
    }
    if (begin > end || end > data_size) {
      Fail(path, where + " bytes [" + std::to_string(begin) + ", " + std::to_string(end) + ") lie outside the " +
                     std::to_string(data_size) + "-byte data (truncated?)");
    }
    if (end - begin != static_cast<uint64_t>(elements) * 4) {
      Fail(path, where + " holds " + std::to_string(end - begin) + " bytes but its shape needs " +
                     std::to_string(elements * 4));
    }
    ranges.emplace_back(begin, end);
    tensor.values.resize(static_cast<size_t>(elements));
    const char* bytes = file.data() + data_begin + begin;
    for (int64_t i = 0; i < elements; ++i) {
      uint32_t bits = 0;
      for (int b = 0; b < 4; ++b) bits |= static_cast<uint32_t>(static_cast<unsigned char>(bytes[4 * i + b])) << (8 * b);
      std::memcpy(&tensor.values[static_cast<size_t>(i)], &bits, 4);
    }
    out.tensors.emplace(name, std::move(tensor));
  }
  std::sort(ranges.begin(), ranges.end());
  for (size_t i = 1; i < ranges.size(); ++i) {
    if (ranges[i].first < ranges[i - 1].second) Fail(path, "two tensors overlap in the data");
  }
  return out;
}

}  // namespace flsd
