#include "skills/runtime/safetensors.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testutil::InputErrorMessage;
using testutil::TempFile;
namespace fs = std::filesystem;

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string LittleEndian64(uint64_t v) {
  std::string out(8, '\0');
  for (int b = 0; b < 8; ++b) out[b] = static_cast<char>((v >> (8 * b)) & 0xff);
  return out;
}

// A file in the format, assembled by hand: the header length, the header text as given (no
// padding), then `data`.
std::string RawFile(const std::string& header, const std::string& data) {
  return LittleEndian64(header.size()) + header + data;
}

// n float32 zeros' worth of bytes.
std::string ZeroBytes(int floats) { return std::string(4 * floats, '\0'); }

uint32_t Bits(float v) {
  uint32_t b;
  std::memcpy(&b, &v, 4);
  return b;
}

// Bitwise, so that NaN, -0.0 and denormals are compared as stored.
void ExpectSameTensor(const FloatTensor& actual, const FloatTensor& expected, const std::string& name) {
  EXPECT_EQ(actual.shape, expected.shape) << name;
  ASSERT_EQ(actual.values.size(), expected.values.size()) << name;
  for (size_t i = 0; i < expected.values.size(); ++i) {
    EXPECT_EQ(Bits(actual.values[i]), Bits(expected.values[i])) << name << "[" << i << "]";
  }
}

// Reads a file that must be rejected; returns the message, which must name the file.
std::string RejectionOf(const std::string& bytes) {
  TempFile file(".safetensors", bytes);
  const std::string message = InputErrorMessage([&] { ReadSafeTensors(file.path()); });
  EXPECT_THAT(message, HasSubstr(file.path()));
  return message;
}

SafeTensors TwoTensors() {
  SafeTensors s;
  s.metadata["format"] = "test";
  s.tensors["a"] = {{2, 2}, {1.0f, 2.0f, 3.0f, 4.0f}};
  s.tensors["b"] = {{3}, {5.0f, 6.0f, 7.0f}};
  return s;
}

TEST(SafeTensors, RoundTripKeepsMetadataAndTensorsExactly) {
  SafeTensors s;
  s.metadata["format"] = "flsd-skill-library";
  s.metadata["text"] = "quotes \" backslash \\ newline \n and UTF-8 \xc3\xa9";
  s.metadata["empty"] = "";
  const float inf = std::numeric_limits<float>::infinity();
  s.tensors["layer.weight"] = {{2, 3},
                               {1.5f, -0.0f, inf, -inf, std::numeric_limits<float>::quiet_NaN(),
                                std::numeric_limits<float>::denorm_min()}};
  s.tensors["layer.bias"] = {{3}, {std::numeric_limits<float>::max(), -1e-30f, 0.1f}};
  s.tensors["scalar"] = {{}, {42.25f}};          // 0-d: one element
  s.tensors["empty"] = {{0}, {}};                // no elements, no bytes
  s.tensors["empty_matrix"] = {{4, 0, 2}, {}};
  const std::string path = testutil::UniqueTempPath("round_trip.safetensors");
  WriteSafeTensors(path, s);
  const SafeTensors r = ReadSafeTensors(path);
  EXPECT_EQ(r.metadata, s.metadata);
  ASSERT_EQ(r.tensors.size(), s.tensors.size());
  for (const auto& [name, tensor] : s.tensors) {
    ASSERT_EQ(r.tensors.count(name), 1u) << name;
    ExpectSameTensor(r.tensors.at(name), tensor, name);
  }
  std::remove(path.c_str());
}

TEST(SafeTensors, NothingAtAllRoundTrips) {
  const std::string path = testutil::UniqueTempPath("empty.safetensors");
  WriteSafeTensors(path, SafeTensors{});
  // "{}" padded to 8 bytes after the 8-byte length.
  EXPECT_EQ(ReadBytes(path), LittleEndian64(8) + "{}      ");
  const SafeTensors r = ReadSafeTensors(path);
  EXPECT_TRUE(r.metadata.empty());
  EXPECT_TRUE(r.tensors.empty());
  std::remove(path.c_str());
}

// Any safetensors reader must be able to open our libraries, so the bytes are checked here
// against the format rather than against our own reader.
TEST(SafeTensors, FileLayoutIsLengthThenPaddedJsonThenLittleEndianFloats) {
  SafeTensors s;
  s.metadata["k"] = "v";
  s.tensors["a"] = {{2}, {1.0f, -2.0f}};
  s.tensors["b"] = {{1}, {0.5f}};
  const std::string path = testutil::UniqueTempPath("layout.safetensors");
  WriteSafeTensors(path, s);
  const std::string bytes = ReadBytes(path);
  std::remove(path.c_str());

  ASSERT_GE(bytes.size(), 8u);
  uint64_t n = 0;
  for (int b = 0; b < 8; ++b) n |= static_cast<uint64_t>(static_cast<unsigned char>(bytes[b])) << (8 * b);
  EXPECT_EQ(n % 8, 0u) << "the data must start 8-byte aligned";
  // 12 bytes of data: a is [0, 8), b is [8, 12).
  ASSERT_EQ(bytes.size(), 8 + n + 12);
  const std::string header = bytes.substr(8, n);
  const size_t json_end = header.find_last_of('}') + 1;
  EXPECT_LT(n - json_end, 8u) << "at most 7 bytes of padding";
  EXPECT_EQ(header.substr(json_end), std::string(n - json_end, ' ')) << "padding must be spaces";
  const nlohmann::json expected = {
      {"__metadata__", {{"k", "v"}}},
      {"a", {{"dtype", "F32"}, {"shape", {2}}, {"data_offsets", {0, 8}}}},
      {"b", {{"dtype", "F32"}, {"shape", {1}}, {"data_offsets", {8, 12}}}},
  };
  EXPECT_EQ(nlohmann::json::parse(header.substr(0, json_end)), expected);
  // 1.0f = 0x3f800000, -2.0f = 0xc0000000, 0.5f = 0x3f000000, each least significant byte first.
  const std::string data = bytes.substr(8 + n);
  const std::string expected_data("\x00\x00\x80\x3f\x00\x00\x00\xc0\x00\x00\x00\x3f", 12);
  EXPECT_EQ(data, expected_data);
}

TEST(SafeTensors, ReadsAHandWrittenFile) {
  // Unpadded header and reversed tensor order in the data: both are valid safetensors.
  const std::string header =
      R"({"x":{"dtype":"F32","shape":[1],"data_offsets":[4,8]},)"
      R"("y":{"dtype":"F32","shape":[],"data_offsets":[0,4]}})";
  const std::string data("\x00\x00\x80\x3f\x00\x00\x00\xc0", 8);  // 1.0f, -2.0f
  TempFile file(".safetensors", RawFile(header, data));
  const SafeTensors r = ReadSafeTensors(file.path());
  EXPECT_TRUE(r.metadata.empty());
  ASSERT_EQ(r.tensors.size(), 2u);
  EXPECT_EQ(r.tensors.at("x").shape, std::vector<int64_t>{1});
  EXPECT_EQ(r.tensors.at("x").values, std::vector<float>{-2.0f});
  EXPECT_TRUE(r.tensors.at("y").shape.empty());
  EXPECT_EQ(r.tensors.at("y").values, std::vector<float>{1.0f});
}

TEST(SafeTensorsErrors, MissingFile) {
  const std::string path = testutil::UniqueTempPath("missing.safetensors");
  EXPECT_THAT(InputErrorMessage([&] { ReadSafeTensors(path); }),
              AllOf(HasSubstr(path), HasSubstr("cannot open")));
}

TEST(SafeTensorsErrors, FileShorterThanTheLengthField) {
  EXPECT_THAT(RejectionOf(std::string("\x10\x00\x00\x00\x00", 5)),
              AllOf(HasSubstr("shorter than the 8-byte"), HasSubstr("5 bytes")));
  EXPECT_THAT(RejectionOf(""), HasSubstr("shorter than the 8-byte"));
}

TEST(SafeTensorsErrors, TruncatedFiles) {
  const std::string path = testutil::UniqueTempPath("whole.safetensors");
  WriteSafeTensors(path, TwoTensors());
  const std::string whole = ReadBytes(path);
  std::remove(path.c_str());
  uint64_t n = 0;
  for (int b = 0; b < 8; ++b) n |= static_cast<uint64_t>(static_cast<unsigned char>(whole[b])) << (8 * b);
  // Cut inside the header: its length now runs past the end.
  EXPECT_THAT(RejectionOf(whole.substr(0, 8 + n - 3)),
              AllOf(HasSubstr("header length"), HasSubstr("truncated")));
  // Cut inside the data: the last tensor's bytes are missing.
  EXPECT_THAT(RejectionOf(whole.substr(0, whole.size() - 4)),
              AllOf(HasSubstr("outside"), HasSubstr("truncated")));
  // Only the length field left.
  EXPECT_THAT(RejectionOf(whole.substr(0, 8)), HasSubstr("header length"));
}

TEST(SafeTensorsErrors, AbsurdHeaderLength) {
  EXPECT_THAT(RejectionOf(LittleEndian64(uint64_t{1} << 63) + "{}"), HasSubstr("header length"));
  EXPECT_THAT(RejectionOf(LittleEndian64(~uint64_t{0}) + "{}"), HasSubstr("header length"));
}

TEST(SafeTensorsErrors, HeaderNotJson) {
  EXPECT_THAT(RejectionOf(RawFile("not json", "")), HasSubstr("header is not JSON"));
  EXPECT_THAT(RejectionOf(RawFile("[1, 2, 3]", "")), HasSubstr("not a JSON object"));
}

TEST(SafeTensorsErrors, DtypeOtherThanF32) {
  EXPECT_THAT(RejectionOf(RawFile(R"({"a":{"dtype":"F16","shape":[2],"data_offsets":[0,4]}})", ZeroBytes(1))),
              AllOf(HasSubstr("tensor 'a'"), HasSubstr("\"F16\"")));
}

TEST(SafeTensorsErrors, OffsetsThatDoNotMatchTheShape) {
  EXPECT_THAT(RejectionOf(RawFile(R"({"a":{"dtype":"F32","shape":[3],"data_offsets":[0,8]}})", ZeroBytes(2))),
              AllOf(HasSubstr("tensor 'a'"), HasSubstr("holds 8 bytes but its shape needs 12")));
  EXPECT_THAT(RejectionOf(RawFile(R"({"a":{"dtype":"F32","shape":[2],"data_offsets":[8,0]}})", ZeroBytes(2))),
              HasSubstr("outside"));
  EXPECT_THAT(RejectionOf(RawFile(R"({"a":{"dtype":"F32","shape":[-1],"data_offsets":[0,0]}})", "")),
              HasSubstr("invalid shape"));
  // 2^62 elements would overflow the byte count.
  EXPECT_THAT(
      RejectionOf(RawFile(R"({"a":{"dtype":"F32","shape":[2147483648,2147483648],"data_offsets":[0,0]}})", "")),
      HasSubstr("invalid shape"));
}

TEST(SafeTensorsErrors, OverlappingTensors) {
  EXPECT_THAT(RejectionOf(RawFile(R"({"a":{"dtype":"F32","shape":[2],"data_offsets":[0,8]},)"
                                  R"("b":{"dtype":"F32","shape":[2],"data_offsets":[4,12]}})",
                                  ZeroBytes(3))),
              HasSubstr("overlap"));
}

TEST(SafeTensorsErrors, MetadataThatIsNotStrings) {
  EXPECT_THAT(RejectionOf(RawFile(R"({"__metadata__":{"n":1}})", "")),
              HasSubstr("__metadata__.n is not a string"));
  EXPECT_THAT(RejectionOf(RawFile(R"({"__metadata__":["x"]})", "")),
              HasSubstr("__metadata__ is not an object"));
}

TEST(SafeTensorsErrors, MalformedTensorEntries) {
  EXPECT_THAT(RejectionOf(RawFile(R"({"a":{"dtype":"F32","shape":[1]}})", ZeroBytes(1))), HasSubstr("lacks"));
  EXPECT_THAT(RejectionOf(RawFile(R"({"a":7})", "")), HasSubstr("lacks"));
  EXPECT_THAT(RejectionOf(RawFile(R"({"a":{"dtype":"F32","shape":"1","data_offsets":[0,4]}})", ZeroBytes(1))),
              HasSubstr("malformed"));
  EXPECT_THAT(RejectionOf(RawFile(R"({"a":{"dtype":"F32","shape":[1],"data_offsets":[0]}})", ZeroBytes(1))),
              HasSubstr("malformed"));
}

// data_offsets must be two integers; anything else is the file's fault and must come out as an
// InputError like every other defect, not as a JSON library exception.
TEST(SafeTensorsErrors, NonNumericDataOffsets) {
  RejectionOf(RawFile(R"({"a":{"dtype":"F32","shape":[1],"data_offsets":["0",4]}})", ZeroBytes(1)));
  RejectionOf(RawFile(R"({"a":{"dtype":"F32","shape":[1],"data_offsets":[0,null]}})", ZeroBytes(1)));
}

TEST(SafeTensorsErrors, WriteIntoAMissingDirectoryNamesThePath) {
  const std::string path = (fs::path(testutil::UniqueTempPath("no_such_dir")) / "lib.safetensors").string();
  EXPECT_THAT(InputErrorMessage([&] { WriteSafeTensors(path, TwoTensors()); }), HasSubstr(path));
}

}  // namespace
}  // namespace flsd
