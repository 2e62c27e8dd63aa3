#pragma once
// DDS in tests: Cyclone on loopback only (configs/cyclonedds_loopback.xml), and a domain and
// partition of the test's own, so tests running in parallel never hear each other.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <functional>
#include <string>

namespace flsd::testutil {

// Points CYCLONEDDS_URI at the loopback config unless the caller set one.
inline void UseLoopbackDds() {
  setenv("CYCLONEDDS_URI", "file://" FLSD_SOURCE_DIR "/configs/cyclonedds_loopback.xml", 0);
}

inline std::string CurrentTestName() {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::string(info->test_suite_name()) + "." + info->name();
}

// A domain id in 100..229 from the test's name.
inline int TestDomainId() { return 100 + static_cast<int>(std::hash<std::string>{}(CurrentTestName()) % 130); }

inline std::string TestPartition() { return "test-" + std::to_string(getpid()) + "-" + CurrentTestName(); }

}  // namespace flsd::testutil
