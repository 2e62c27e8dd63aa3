#pragma once
// Starts the real skilld (sim backend, shipped library) on a loopback domain and partition of the
// test's own, and stops it at the end of the test.

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "tests/common/dds_support.h"
#include "tests/common/process.h"
#include "tests/common/test_support.h"

namespace flsd::testutil {

class SkilldFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    UseLoopbackDds();
    domain_ = TestDomainId();
    partition_ = TestPartition();
  }

  void StartServer(const std::string& backend = "sim",
                   const std::string& config = FLSD_SOURCE_DIR "/configs/server.yaml") {
    const std::vector<std::string> args = {"--backend", backend, "--library",
                                           FLSD_SOURCE_DIR "/models/a1_flsd.safetensors", "--config", config,
                                           "--domain", std::to_string(domain_), "--partition", partition_};
    server_ = std::make_unique<Process>(BinaryPath("skilld"), args, UniqueTempPath("skilld.log"));
  }

  // skillctl's arguments for this test's server.
  std::vector<std::string> SkillctlArgs(std::vector<std::string> command) const {
    std::vector<std::string> args = {"--domain", std::to_string(domain_), "--partition", partition_, "--timeout", "10"};
    args.insert(args.end(), command.begin(), command.end());
    return args;
  }

  std::pair<int, std::string> Skillctl(const std::vector<std::string>& command) {
    return RunProgram(BinaryPath("skillctl"), SkillctlArgs(command), UniqueTempPath("skillctl" + std::to_string(runs_++) + ".log"));
  }

  int domain_ = 0;
  std::string partition_;
  std::unique_ptr<Process> server_;
  int runs_ = 0;
};

}  // namespace flsd::testutil
