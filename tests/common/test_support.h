#pragma once
// Small helpers shared by the unit tests: catching InputError messages and writing scratch files.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

#include "core/check.h"

namespace flsd::testutil {

// What a track_velocity reply says of an axis the selector clipped: "vx clipped to 0.87".
inline std::string ClippedTo(const char* axis, double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%s clipped to %.2f", axis, value);
  return text;
}

// Runs `f` and returns the message of the InputError it throws; records a failure (and returns
// "") if it throws nothing or something else, so that message checks on "" fail loudly too.
template <class F>
std::string InputErrorMessage(F&& f) {
  try {
    std::forward<F>(f)();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected flsd::InputError, got another exception: " << e.what();
    return "";
  }
  ADD_FAILURE() << "expected flsd::InputError, nothing was thrown";
  return "";
}

// A path under the system temp directory that no other test (or concurrent ctest process) uses:
// it carries the process id, the running test's name and `tag`.
inline std::string UniqueTempPath(const std::string& tag) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = "flsd_" + std::to_string(getpid()) + "_" + info->test_suite_name() + "_" +
                     info->name() + "_" + tag;
  for (char& c : name) {
    if (c == '/') c = '_';  // parameterised test names contain slashes
  }
  return (std::filesystem::temp_directory_path() / name).string();
}

// A file with the given contents, removed when it goes out of scope.
class TempFile {
 public:
  TempFile(const std::string& suffix, const std::string& contents)
      : path_(UniqueTempPath(std::to_string(counter_++) + suffix)) {
    std::ofstream out(path_);
    out << contents;
  }
  ~TempFile() { std::remove(path_.c_str()); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  const std::string& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  std::string path_;
};

// A path for a file the test writes, removed when it goes out of scope.
class ScratchFile {
 public:
  explicit ScratchFile(const std::string& suffix) : path_(UniqueTempPath(suffix)) {}
  ~ScratchFile() { std::filesystem::remove(path_); }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// The bytes of a file ("" if it cannot be read).
inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

}  // namespace flsd::testutil
